// dualcell-fit: the effective bilinear tension/compression law from a sweep.
//
// Per direction: E_tension, E_compression (apparent plane-strain moduli s/ε_nn, least squares
// through the origin on the points before any break) with standard errors and R², Poisson's
// ratios, and where adhesion breaks the fuse stress, strain jump and the modulus past it; over
// all directions the in-plane compliances S_tension, S_compression with their residuals and
// definiteness, the cone-wise linear check, the cone-wise law before and after the fuse, and
// the exact onset surface checked against the sweep, and with an exact law the small cell fitted
// to it. Writes law.h5 (layout: docs/reference/law-h5.md).
//
//   dualcell-fit --sweep sweep.h5 --out law.h5 [--law-tolerance 0.02] [--no-small-cell]

#include "apps/options.hpp"
#include "fit/fit.hpp"
#include "stage/fit.hpp"
#include "stage/stage.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "dualcell-fit: fit the bilinear tension/compression law to a sweep and write law.h5\n"
      "(layout: docs/reference/law-h5.md)."};
  std::string sweep_file, out;
  dualcell::fit::FitOptions options;
  bool no_small_cell = false, quiet = false;
  app.add_option("--sweep", sweep_file, "sweep.h5 written by dualcell-sweep")->required();
  app.add_option("--out", out, "output HDF5 file")->required();
  app.add_option("--law-tolerance", options.law_tolerance,
                 "the small cell's largest stress error over the sphere (relative): its rows grow until it holds")
      ->capture_default_str()
      ->check(dualcell::number_in(1e-6, 1.0));
  app.add_flag("--no-small-cell", no_small_cell,
               "fit no small cell (with adhesion its ladder is most of a fit); the exact law and the cone-wise laws "
               "are fitted and checked as ever");
  app.add_flag("--quiet", quiet, "no progress and no table");
  if (const auto stop = dualcell::parse_options(app, argc, argv)) return *stop;

  return dualcell::run_stage("dualcell-fit", [&] {
    using namespace dualcell;
    options.small_cell = !no_small_cell;
    const law::Law law = stage::run_fit(sweep_file, out, options, !quiet);
    if (!quiet) stage::print_fit_summary(sweep_file, out, law);
  });
}
