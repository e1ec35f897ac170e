#pragma once
// The fit and export stages as one call each (dualcell-fit, dualcell-export): a sweep.h5 to a
// law.h5, and a law.h5 to JSON, CSV or CalculiX cards (conversions in io/law_export.hpp).
#include <filesystem>
#include <string>

#include "io/law_export.hpp"
#include "law/law.hpp"

namespace dualcell::stage {

// Reads the sweep (refusing a foreign, truncated or incomplete file), fits the law, records the
// sweep file and its hash in the law's provenance, and writes law.h5 atomically.
law::Law run_fit(const std::filesystem::path& sweep_file, const std::filesystem::path& out);
// dualcell-fit's summary on stdout: per direction the measured moduli, the compliances, the
// cone-wise laws with their apparent moduli beside the measured ones, the onset surface's check.
void print_fit_summary(const std::filesystem::path& sweep_file, const std::filesystem::path& out, const law::Law& law);

struct ExportOptions {
  std::filesystem::path law_file, out;
  io::ExportFormat format = io::ExportFormat::json;
  std::string name = "DUALCELL";  // CalculiX material base name: a letter, then letters, digits, _
  // The umat carries the compact cone-wise law: refused when it misses the exact law by more
  // than this (the largest relative stress error of /law/cone_check), unless forced.
  double max_law_error = 0.02;
  bool force = false;
  // umat: "cell" (the exact law, its cell in io::umat_cell_file(cell_id) beside `out`), "cone",
  // or "" for the exact law where law.h5 has one.
  std::string form;
  int cell_id = 1;
};

// Reads law_file, converts, writes `out` atomically (nothing is left behind on any error) and
// returns a one-line description of what was written.
std::string export_law(const ExportOptions& options);

// dualcell-law: a law evaluated at the points of a CSV file (io/points_csv.hpp), strain- or
// stress-driven, in its exact form (the condensed cell, /law/cell) or its compact one (the
// cone-wise law with the fuse, /law/cone and /law/cone_after_fuse as the umat evaluates it).
enum class LawForm { cell, cone };
struct LawPointsOptions {
  std::filesystem::path law_file, points_file, out;
  bool strain_driven = true;
  LawForm form = LawForm::cell;
};
struct LawPointsSummary {
  int rows = 0, paths = 0;     // paths: loading paths with history (rows without a path count one each)
  double seconds = 0;          // of the evaluations alone
  long qp_iterations = 0;      // the cell form's active-set subproblems, all rows
  long qp_factorisations = 0;  // of which needed a new factorisation
};
// Writes `out` atomically: per input row the other quantity, dσ/dε (9 entries, row by row,
// engineering shear) and the broken bonds (cell: pairs broken; cone: 1 once fused).
LawPointsSummary evaluate_law(const LawPointsOptions& options);

}  // namespace dualcell::stage
