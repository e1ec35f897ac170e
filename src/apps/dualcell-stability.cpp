// dualcell-stability: the stability matrix on stiff and extreme cases (study/stability.hpp).
// Writes a CSV with one row per case and a Markdown summary; exits 3 (an internal error) when a
// case failed: a silent NaN/Inf or a stop without a diagnostic is a fault of the solver, not of
// the input.
//
//   dualcell-stability --out stability.csv [--summary stability.md] [--fast]
#include <unistd.h>

#include <cstdio>

#include "apps/options.hpp"
#include "stage/stage.hpp"
#include "study/stability.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "dualcell-stability: run the solver over stiffness contrasts, Poisson ratios, fibre sizes and\n"
      "positions, adhesion, load magnitudes, directions and boundary conditions; write a table."};
  dualcell::study::StabilityOptions options;
  app.add_option("--out", options.csv, "CSV, one row per case")->required();
  app.add_option("--summary", options.summary, "Markdown summary (per boundary and factor)");
  app.add_flag("--fast", options.fast, "the subset the test suite runs");
  app.add_option("--tolerance", options.tolerance, "solver tolerance")->check(dualcell::number_in(1e-14, 1e-2));
  if (const auto stop = dualcell::parse_options(app, argc, argv)) return *stop;

  int failed = 0;
  const int status = dualcell::run_stage("dualcell-stability", [&] {
    options.progress = ::isatty(2);
    const auto report = dualcell::study::run_stability(options);
    failed = report.failed;
    std::printf("dualcell-stability: %d cases, %d failed, %d stopped with a diagnostic -> %s\n", report.cases,
                report.failed, report.stopped, options.csv.c_str());
  });
  return status != dualcell::exit_ok ? status : (failed > 0 ? dualcell::exit_internal_error : dualcell::exit_ok);
}
