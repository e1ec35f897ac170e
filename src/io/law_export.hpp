#pragma once
// The exports of a law.h5 (docs/guide/export.md): JSON for scripts, CSV with one
// row per direction, CalculiX/Abaqus material cards (the 3D materials of law/solid.hpp) and the
// constants of dualcell's umat.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "law/form.hpp"
#include "law/law.hpp"
#include "law/solid.hpp"

namespace dualcell::io {

enum class ExportFormat { json, csv, calculix, umat };

// "json", "csv", "calculix" or "umat"; anything else is an InputError.
ExportFormat parse_export_format(const std::string& text);

// Everything in law.h5 as one JSON object, keys named as the objects of law.h5 (datasets of
// shape (1) as numbers, 3×3 as row arrays); NaN and infinities as null.
std::string law_json(const law::Law& law);
// A header line and one row per direction: the per-direction datasets of law.h5 and the two
// fits' per-direction residuals; NaN as "nan".
std::string law_csv(const law::Law& law);
// Two *MATERIALs, <name>_TENSION and <name>_COMPRESSION, with comment lines stating the axes,
// units, formulas and provenance. `source` is the law file named in the comments.
std::string law_calculix(const law::Law& law, const std::string& name, const std::string& source);

// The constants of the user material src/umat/dualcell_umat.c (its header gives the layout):
// the bonded cone-wise law, the law past the fuse and the onset facets when the law has both
// (otherwise K_a = F = 0: the points never fuse), and the out-of-plane E33, G13 = G23 by the
// rule of mixtures. Refuses a law without a fitted cone-wise law.
std::vector<double> umat_constants(const law::Law& law, const std::string& file);
// The *MATERIAL card ABAQUS_<name> (*USER MATERIAL with umat_constants, *DEPVAR 1) with comment
// lines stating the layout, axes, units and provenance.
std::string law_umat(const law::Law& law, const std::string& name, const std::string& source);
// The exact law for the same umat (layout 2): the card ABAQUS_<name> with constants 2, `id`,
// E33, G13, G23, the cell file's hash (text_hash_value of its text, high and low 32 bits)
// and *DEPVAR 1 + pairs + 3 + rows (src/umat/cell_umat.h); the cell itself goes to the file
// umat_cell_file(id) beside the card (law/cell_text.hpp). The same for the small cell (a cell of
// the same form, /law/small). A cell of the whole ply (the strain and the shears along the
// fibres: macro = "full", periodic) gets layout 3 instead: constants 3, `id`, the hash, all six
// components from the cell (no rule of mixtures), *DEPVAR 1 + pairs + 3 + rows + shear rows.
// Refuses a law without the one asked for. `form`: law::LawForm::cell or small.
// The cell the umat carries for `form`; refuses (InputError naming `source` and the object) a law
// without it (law::pick_form), or one without shear (the symmetry boundary).
const law::CondensedCell& umat_cell(const law::Law& law, law::LawForm form, const std::string& source);
// Where a material point's bonds break (umat/cell_umat.h): within each increment (its debond
// cascade at every strain), or between increments (held within one, the cascade's breaks at its
// end taking effect in the next: a 5th constant 1, layout 3 only). `stress_free_temperature`: the
// temperature T0 at which the cell is stress-free, in the analysis' scale (layout 3 of a cell that
// carries a temperature change only: a 6th constant; the umat evaluates at ΔT = T − T0).
enum class UmatBreaks { within, between };
std::string law_umat_cell(const law::Law& law, law::LawForm form, const std::string& name, int id,
                          std::uint64_t cell_hash, const std::string& source, UmatBreaks breaks = UmatBreaks::within,
                          std::optional<double> stress_free_temperature = std::nullopt);
std::string umat_cell_file(int id);
// The card's hash constants as written (6 and 7 of layout 2, 3 and 4 of layout 3): the cell
// file's hash, high and low 32 bits.
std::string umat_cell_hash_constants(std::uint64_t hash);

}  // namespace dualcell::io
