// The user material's cards (dualcell-export --format umat): the cone-wise law's constants
// (layout 1) and the cards of a cell's exact law or small cell (layouts 2 and 3), with the cell's
// text file beside them (docs/guide/calculix.md; the umat itself is src/umat/).
#include <cstdint>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/text.hpp"
#include "io/card_text.hpp"
#include "io/law_export.hpp"
#include "law/solid.hpp"

namespace dualcell::io {

using namespace law;

std::vector<double> umat_constants(const Law& law, const std::string& file) {
  if (!law.cone.ok)
    throw InputError(file + ": /law/cone: no fitted cone-wise law (" + one_line(law.cone.message) +
                     "): there is no law for a user material");
  check_constituents(law, file);
  const OutOfPlane z = out_of_plane(law);
  const bool fuse = law.cone_after_fuse.ok && law.onset.linear && law.onset.facets.rows() > 0;
  const auto planes = [](const ConeLaw& l) { return static_cast<double>(l.q.size()); };
  std::vector<double> k = {1.0,
                           planes(law.cone.law),
                           fuse ? planes(law.cone_after_fuse.law) : 0.0,
                           fuse ? static_cast<double>(law.onset.facets.rows()) : 0.0,
                           z.E3,
                           z.G13,
                           z.G23};
  const auto add_law = [&](const ConeLaw& l) {
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) k.push_back(l.C_c(i, j));
    for (std::size_t p = 0; p < l.q.size(); ++p) k.insert(k.end(), {l.q[p](0), l.q[p](1), l.q[p](2), l.beta[p]});
  };
  add_law(law.cone.law);
  if (fuse) {
    add_law(law.cone_after_fuse.law);
    for (Eigen::Index f = 0; f < law.onset.facets.rows(); ++f)
      k.insert(k.end(), {law.onset.facets(f, 0), law.onset.facets(f, 1), law.onset.facets(f, 2)});
  }
  return k;
}

std::string law_umat(const Law& law, const std::string& name, const std::string& source) {
  check_name(name);
  const std::vector<double> k = umat_constants(law, source);
  const bool fuse = k[2] > 0;
  std::string out = card_header(law, source, "cone-wise law as a user material");
  out +=
      "** For a code built with dualcell's umat (src/umat/dualcell_umat.c; CalculiX: make -C pipelines ccx-umat).\n"
      "** Plane strain in the x-y plane (CPE*): sigma = C_c eps + sum_k beta_k <q_k.eps>+ q_k in (11, 22, 12),\n"
      "** engineering shear; out of plane decoupled: E33, G13, G23 (" +
      std::string(out_of_plane(law).from_cell ? "the cell's, /law/ply" : "rule of mixtures") + ").\n";
  out += fuse ? "** The fuse: a point whose stress leaves the onset surface (max_f g_f.sigma >= 1) switches to the\n"
                "** law past the fuse for good (state variable 1: 0 bonded, 1 fused).\n"
              : "** No fuse: the law has no onset surface or no law past the fuse; points stay bonded.\n";
  out += "** Constants: version 1, K_b = " + formatted("%.0f", k[1]) + " planes, K_a = " + formatted("%.0f", k[2]) +
         " planes past the fuse, F = " + formatted("%.0f", k[3]) +
         " facets, E33, G13, G23;\n"
         "** then C_c (row by row) and c1, c2, c3, beta per plane, bonded then past the fuse; then the facets.\n";
  // CalculiX reads CONSTANTS/8 + 1 lines (a temperature after the last constant), so a count
  // that is a multiple of 8 would need a line Abaqus does not expect: one trailing 0 (which the
  // umat ignores) keeps both readers happy.
  std::vector<double> padded = k;
  if (padded.size() % 8 == 0) padded.push_back(0.0);
  out += "*MATERIAL, NAME=ABAQUS_" + name + "\n";
  out += "*USER MATERIAL, CONSTANTS=" + std::to_string(padded.size()) + "\n";
  for (std::size_t i = 0; i < padded.size(); ++i)
    out += card_number(padded[i]) + (i + 1 == padded.size() ? "\n" : (i % 8 == 7 ? ",\n" : ", "));
  out += "*DEPVAR\n1\n";
  return out;
}

std::string umat_cell_file(int id) { return "dualcell-cell-" + std::to_string(id) + ".txt"; }

std::string umat_cell_hash_constants(std::uint64_t hash) {
  return card_number(static_cast<double>(hash >> 32)) + ", " + card_number(static_cast<double>(hash & 0xffffffffULL));
}

const law::CondensedCell& umat_cell(const Law& law, law::LawForm form, const std::string& source) {
  if (form == law::LawForm::cone) throw std::invalid_argument("umat_cell: the cone-wise law has no cell");
  const std::string object = form == law::LawForm::small ? "/law/small" : "/law/cell";
  const law::CondensedCell* kept = &law::cell_of(law, law::pick_form(law, law::to_string(form), source));
  if (kept->n_macro != 3)
    throw InputError(source + ": " + object +
                     ": the cell has the symmetry boundary and carries no shear: a material "
                     "point needs all three stresses (--form cone writes the cone-wise law)");
  return *kept;
}

namespace {

// Layout 3: the whole ply's exact law or its small cell, every component from the cell.
std::string law_umat_ply(const Law& law, const law::CondensedCell& cell, bool small, const std::string& name, int id,
                         std::uint64_t cell_hash, const std::string& source, UmatBreaks breaks,
                         std::optional<double> stress_free_temperature) {
  const bool between = breaks == UmatBreaks::between;
  if (stress_free_temperature && cell.thermal == 0)
    throw InputError(source + ": --stress-free-temperature: the " + (small ? "small cell" : "cell") +
                     " carries no temperature change (the exact law of phases that both have alpha, fitted with "
                     "adhesion and [load] macro = \"full\", does)");
  const int depvar = 1 + cell.n_pairs + cell.n_macro + cell.n_rows() + cell.shear_rows;
  std::string out = card_header(
      law, source,
      small ? "small cell of the whole ply as a user material" : "exact law of the whole ply as a user material");
  out +=
      "** For a code built with dualcell's umat (src/umat/dualcell_umat.c; CalculiX: make -C pipelines ccx-umat).\n"
      "** Every element (C3D*, CPE*, ...): material axes 1 = x, 2 = y in the plane of the cells, 3 = z along\n"
      "** the fibres; all six components from " +
      (small ? "the small cell fitted to the exact law (" + std::to_string(cell.n_rows()) + " rows and " +
                   std::to_string(cell.shear_rows) + " shear rows, " +
                   formatted("%.2g", 100 * law.small_ply_check.max_error) +
                   " % largest stress error against it\n** along six-component strain paths),"
             : "the cell condensed onto its " + std::to_string(cell.n_rows()) + " interface rows and " +
                   std::to_string(cell.shear_rows) + " shear rows,") +
      "\n** read from " + umat_cell_file(id) +
      " (in $DUALCELL_CELL_DIR or the working directory). Each material point carries\n"
      "** its bonds (state variables 2 to " +
      std::to_string(1 + cell.n_pairs) +
      ", 1 where a pair broke) and the warm starts of its QPs (src/umat/cell_umat.h).\n"
      "** Constants: layout 3, law id, the cell file's hash (FNV-1a, high and low 32 bits: a file replaced\n"
      "** after this card was written is refused, not mixed with it)" +
      std::string(between ? ", 1: bonds break between increments\n"
                            "** (held within one; the pairs its cascade breaks at its end break at the start of the "
                            "next: repeat\n** an increment at the same load until none does).\n"
                          : ".\n");
  if (stress_free_temperature)
    out +=
        "** 6th constant: the stress-free temperature T0; each point at dT = T - T0 with the total strain\n"
        "** (give the temperatures: *INITIAL CONDITIONS, TYPE=TEMPERATURE and *TEMPERATURE; no *EXPANSION).\n";
  out += "*MATERIAL, NAME=ABAQUS_" + name + "\n";
  out += std::string("*USER MATERIAL, CONSTANTS=") + (stress_free_temperature ? "6" : between ? "5" : "4") + "\n";
  out += card_number(3) + ", " + card_number(id) + ", " + umat_cell_hash_constants(cell_hash) +
         (between || stress_free_temperature ? ", " + card_number(between ? 1 : 0) : "") +
         (stress_free_temperature ? ", " + card_number(*stress_free_temperature) : "") + "\n";
  out += "*DEPVAR\n" + std::to_string(depvar) + "\n";
  return out;
}

}  // namespace

std::string law_umat_cell(const Law& law, law::LawForm form, const std::string& name, int id, std::uint64_t cell_hash,
                          const std::string& source, UmatBreaks breaks, std::optional<double> stress_free_temperature) {
  check_name(name);
  const bool small = form == law::LawForm::small;
  const law::CondensedCell& cell = umat_cell(law, form, source);
  if (cell.longitudinal == 1 && cell.shear == 2)
    return law_umat_ply(law, cell, small, name, id, cell_hash, source, breaks, stress_free_temperature);
  if (stress_free_temperature)
    throw InputError(source +
                     ": --stress-free-temperature: only for a cell of the whole ply (the umat's layout 3: [load] "
                     "macro = \"full\", periodic)");
  if (breaks == UmatBreaks::between)
    throw InputError(source +
                     ": --breaks between: only for a cell of the whole ply (the umat's layout 3: [load] "
                     "macro = \"full\", periodic)");
  check_constituents(law, source);
  const OutOfPlane z = out_of_plane(law);
  const int depvar = 1 + cell.n_pairs + cell.n_macro + cell.n_rows();
  std::string out = card_header(
      law, source,
      small ? "small cell of the exact law as a user material" : "exact law of the cell as a user material");
  out +=
      "** For a code built with dualcell's umat (src/umat/dualcell_umat.c; CalculiX: make -C pipelines ccx-umat).\n"
      "** Plane strain in the x-y plane (CPE*): " +
      (small ? "the small cell fitted to the exact law (" + std::to_string(cell.n_rows()) + " rows, " +
                   formatted("%.2g", 100 * law.small_check.max_error) +
                   " % largest stress error against it), read from\n** "
             : "the cell condensed onto its " + std::to_string(cell.n_rows()) + " interface rows, read from\n** ") +
      umat_cell_file(id) +
      " (in $DUALCELL_CELL_DIR or the working directory); out of plane decoupled:\n"
      "** E33, G13, G23 (rule of mixtures). Each material point carries its bonds (state variables 2 to " +
      std::to_string(1 + cell.n_pairs) +
      ",\n** 1 where a pair broke) and the warm start of its QP (src/umat/cell_umat.h).\n"
      "** Constants: layout 2, law id, E33, G13, G23, the cell file's hash (FNV-1a, high and low 32 bits:\n"
      "** a file replaced after this card was written is refused, not mixed with it).\n";
  out += "*MATERIAL, NAME=ABAQUS_" + name + "\n";
  out += "*USER MATERIAL, CONSTANTS=7\n";
  out += card_number(2) + ", " + card_number(id) + ", " + card_number(z.E3) + ", " + card_number(z.G13) + ", " +
         card_number(z.G23) + ", " + umat_cell_hash_constants(cell_hash) + "\n";
  out += "*DEPVAR\n" + std::to_string(depvar) + "\n";
  return out;
}

}  // namespace dualcell::io
