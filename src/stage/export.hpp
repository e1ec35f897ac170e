#pragma once
// The export stage as one call (dualcell-export): a law.h5 to JSON, CSV, CalculiX cards or the
// umat's card (conversions in io/law_export.hpp).
#include <filesystem>
#include <limits>
#include <optional>
#include <string>

#include "io/law_export.hpp"

namespace dualcell::stage {

struct ExportOptions {
  std::filesystem::path law_file, out;
  io::ExportFormat format = io::ExportFormat::json;
  std::string name = "DUALCELL";  // CalculiX material base name: a letter, then letters, digits, _
  // The umat carries a compact law (cone-wise, small cell): refused when it misses the exact law
  // by more than this (the largest relative stress error of its check), unless forced. NaN, the
  // default: the tolerance the law was fitted to (/law/small_fit tolerance, dualcell-fit
  // --law-tolerance), or fit::default_law_tolerance where it records none.
  double max_law_error = std::numeric_limits<double>::quiet_NaN();
  bool force = false;
  // umat: "cell" (the exact law, its cell in io::umat_cell_file(cell_id) beside `out`), "small"
  // (its small cell, likewise), "cone", or "" for the default (law::pick_form).
  std::string form;
  int cell_id = 1;
  // umat of a cell: where its bonds break ("within" each increment, the default, or "between").
  std::string breaks;
  // umat of a whole ply's cell that carries a temperature change: the stress-free temperature T0
  // (the card's 6th constant; io::law_umat_cell).
  std::optional<double> stress_free_temperature;
};

// Reads law_file, converts, writes `out` atomically (nothing is left behind on any error) and
// returns a one-line description of what was written.
std::string export_law(const ExportOptions& options);

}  // namespace dualcell::stage
