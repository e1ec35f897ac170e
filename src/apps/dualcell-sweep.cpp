// dualcell-sweep: load paths in magnitude and direction through the dual solver.
//
// For every path of the scene ([sweep] directions_deg × {tension, compression}, and the
// general stress_directions), steps through the magnitudes from the intact, unloaded state,
// carrying the bond state, inserting the exact debond onset and bracketing every jump (the
// fuse) by bisection (docs/method.md). Finished paths are journaled in <out>.parts/, so an
// interrupted run resumes; the final sweep.h5 appears complete at the end (stage/sweep.hpp).
//
//   dualcell-sweep --config scene.toml --mesh mesh.h5 --out sweep.h5

#include <cstdio>

#include "apps/options.hpp"
#include "stage/stage.hpp"
#include "stage/sweep.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "dualcell-sweep: sweep load paths (directions x tension/compression x magnitudes) with bond history\n"
      "and the fuse; writes sweep.h5 (layout: docs/reference/sweep-h5.md). Resumes an interrupted run."};
  dualcell::stage::SweepOptions options;
  bool quiet = false;
  app.add_option("--config", options.scene_file, "scene file (TOML)")->required();
  app.add_option("--mesh", options.mesh_file, "mesh.h5 made by dualcell-mesh from the same scene")->required();
  app.add_option("--out", options.out, "output HDF5 file")->required();
  app.add_flag("--quiet", quiet, "no progress on stderr");
  app.add_option("--threads", options.threads,
                 "threads for the subdomain work; 0 = OMP_NUM_THREADS or all cores (results do not depend on it)")
      ->check(dualcell::number_in(0, 4096));
  app.add_option("--ranks-per-path", options.ranks_per_path,
                 "under mpirun: ranks that solve one path together, sharing its subdomains (default 1: each rank "
                 "solves whole paths; results do not depend on it)")
      ->check(dualcell::number_in(1, 1 << 20));
  // For tests of the resume: stop dead (as kill -9 would) after this many finished paths.
  app.add_option("--interrupt-after-paths", options.interrupt_after, "")->group("");
  if (const auto stop = dualcell::parse_options(app, argc, argv)) return *stop;

  // Steps that did not converge are written and marked (sweep.h5 /paths/NNN/converged):
  // exit 4, as every stage whose computation ran without converging.
  int exit_code = dualcell::exit_ok;
  const int status = dualcell::run_stage(
      "dualcell-sweep",
      [&] {
        options.progress = !quiet;
        const auto s = dualcell::stage::run_sweep(options);
        if (s.unconverged_steps > 0) exit_code = dualcell::exit_not_converged;
        if (s.written && s.unconverged_steps > 0)
          std::fprintf(stderr, "dualcell-sweep: warning: %d steps did not converge (written, marked as such)\n",
                       s.unconverged_steps);
        if (!quiet && s.written)
          std::printf("dualcell-sweep: %d paths -> %s (%d with a fuse, %d steps not converged, %d resumed), %.2f s\n",
                      s.paths, options.out.c_str(), s.fuses, s.unconverged_steps, s.resumed, s.seconds);
        if (!quiet && s.written)
          std::printf("dualcell-sweep: dual operator %s: explicit in %d of %d subdomains\n", s.dual_operator.c_str(),
                      s.explicit_subdomains, s.subdomains);
        if (!quiet && s.written && s.cell_rows > 0)
          std::printf("dualcell-sweep: exact law: the cell condensed onto %d interface rows, %.0f kB, in %.2f s\n",
                      s.cell_rows, s.cell_bytes / 1e3, s.cell_seconds);
        if (!quiet && s.written && s.cell_rows == 0)
          std::printf("dualcell-sweep: no exact law: %s\n", s.cell_note.c_str());
        if (!quiet && s.written && s.basis_rows > 0)
          std::printf("dualcell-sweep: the cell on %d of its own solutions (the small cell's start) in %.1f s\n",
                      s.basis_rows, s.basis_seconds);
      },
      dualcell::Ranks::share);
  return status != dualcell::exit_ok ? status : exit_code;
}
