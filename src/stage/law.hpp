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
};

// Reads law_file, converts, writes `out` atomically (nothing is left behind on any error) and
// returns a one-line description of what was written.
std::string export_law(const ExportOptions& options);

}  // namespace dualcell::stage
