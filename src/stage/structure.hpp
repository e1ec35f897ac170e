#pragma once
// The structure stage as one call (dualcell-structure): a structure scene and a law.h5 to
// structure.h5 (+ XDMF), every load step with the fuse.
#include <filesystem>
#include <vector>

#include "structure/structure.hpp"

namespace dualcell::stage {

struct StructureOptions {
  std::filesystem::path scene_file, law_file, out;
  // The law every point follows: "cell" (the exact law, /law/cell), "cone" (the compact
  // cone-wise law with the fuse per cell), or "" for the exact law where law.h5 has one.
  std::string form;
  bool progress = true;  // one line per load step on stderr
};

struct StructureSummary {
  std::vector<structure::StepResult> steps;
  int n_nodes = 0, n_triangles = 0, fused_cells = 0, n_cells = 0;
  std::string law_form;               // "cell" or "cone": the law used
  int broken_units = 0, n_units = 0;  // exact law: units with a broken bond at the end, of all
  std::string bond_unit;              // exact law: "cell" or "point" (StructureScene::bond_unit)
  double cell_size = 0, seconds = 0;
  double first_fuse_factor = 0;  // structure::HomogenisedStructure::first_fuse_factor
  std::string fuse_note;         // why cells cannot fuse, when they cannot
};

// The cell law of a law.h5 for a structure. `form` "cone": the bonded cone-wise law, the law
// past the fuse and the onset surface; without a law past the fuse or an onset surface the cells
// keep the bonded law (`note` says why); a law.h5 without a fitted cone-wise law is refused.
// "cell": the exact law /law/cell (refused when law.h5 has none: cell_note says why). "": the
// exact law where there is one, else the cone-wise law (`note` says why). `form` is set to the
// one chosen.
structure::CellLaw cell_law(const std::filesystem::path& law_file, std::string& form, double& cell_size,
                            std::string& note);

StructureSummary run_structure(const StructureOptions& options);

}  // namespace dualcell::stage
