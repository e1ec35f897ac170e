#pragma once
// The fit stage as one call (dualcell-fit): a sweep.h5 to a law.h5, and its summary.
#include <filesystem>

#include "fit/fit.hpp"
#include "law/law.hpp"

namespace dualcell::stage {

// Reads the sweep (refusing a foreign, truncated or incomplete file), fits the law, records the
// sweep file and its hash in the law's provenance, and writes law.h5 atomically.
// `options`: what the fit makes (fit::FitOptions).
// `progress`: the fit's long parts on stderr as the sweep shows its own (core/progress.hpp).
law::Law run_fit(const std::filesystem::path& sweep_file, const std::filesystem::path& out,
                 const fit::FitOptions& options, bool progress = false);
// dualcell-fit's summary on stdout: per direction the measured moduli, the compliances, the
// cone-wise laws with their apparent moduli beside the measured ones, the onset surface's check.
void print_fit_summary(const std::filesystem::path& sweep_file, const std::filesystem::path& out, const law::Law& law);

}  // namespace dualcell::stage
