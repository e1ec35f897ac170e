// dualcell-solve: one load case through the dual contact/adhesion solver.
//
// Reads the scene and its mesh, applies the macroscopic stress σ̄ = (σxx, σyy, σxy) through the
// scene's boundary condition, solves the Total FETI dual problem with SMALBE/MPRGP (breaking
// bonds at their strength and re-solving; docs/method.md), recovers u, and writes solution.h5
// with an XDMF of the deformed shape (gaps visible). Prints a one-screen summary with the time
// of each phase.
//
//   dualcell-solve --config scene.toml --mesh mesh.h5 --stress 0.01,0,0 --out solution.h5
//   dualcell-solve --config scene.toml --mesh mesh.h5 --stress 0,0,0 --eps33 0.01 --out solution.h5
//   dualcell-solve --config beam.toml --mesh mesh.h5 --out solution.h5   ([load] boundary = "edges")
//   mpirun -np 4 dualcell-solve ...   (the subdomains shared out over 4 ranks; one solution.h5)
#include <cstdio>

#include "apps/options.hpp"
#include "stage/solve.hpp"
#include "stage/stage.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "dualcell-solve: one macroscopic stress through the dual (Total FETI) contact/adhesion solver.\n"
      "Writes solution.h5 and solution.xdmf (layout: docs/reference/solution-h5.md)."};
  dualcell::stage::SolveOptions options;
  bool quiet = false;
  app.add_option("--config", options.scene_file, "scene file (TOML)")->required();
  app.add_option("--mesh", options.mesh_file, "mesh.h5 made by dualcell-mesh from the same scene")->required();
  app.add_option("--stress", options.stress_text,
                 "macroscopic stress sxx,syy,sxy (tensor shear); required but with boundary = \"edges\", whose "
                 "loads and steps are in the scene");
  app.add_option("--eps33", options.eps33,
                 "longitudinal strain e33 along the fibres (generalised plane strain, docs/method.md §3a); "
                 "default 0: plane strain")
      ->check(dualcell::number_in(-1.0, 1.0));
  app.add_flag("--longitudinal-shear", options.longitudinal_shear,
               "also the cell's longitudinal shear moduli Gxz, Gyz with the bonds this load left (periodic "
               "boundary; docs/method.md §3b)");
  app.add_flag("--onset", options.onset,
               "also the debond onset along this stress: the factor s at which the first bond of the intact "
               "interface reaches its strength under s*stress, from the cool-down where the scene has delta_T "
               "(docs/method.md §1a, §11; a scene with adhesion, without --eps33)");
  app.add_option("--out", options.out, "output HDF5 file; the XDMF file is written beside it")->required();
  app.add_option("--bonds", options.bonds_file,
                 "solution.h5 whose /interface/bonded is the bond state before this load (default: intact)");
  app.add_flag("--quiet", quiet, "no progress and no summary");
  app.add_option("--threads", options.threads,
                 "threads for the subdomain work; 0 = OMP_NUM_THREADS or all cores (results do not depend on it)")
      ->check(dualcell::number_in(0, 4096));
  if (const auto stop = dualcell::parse_options(app, argc, argv)) return *stop;
  options.progress = !quiet;

  int exit_code = dualcell::exit_ok;
  const int status = dualcell::run_stage(
      "dualcell-solve",
      [&] {
        using namespace dualcell;
        const stage::SolveOutcome outcome = stage::run_solve(options);
        const feti::Solution& s = outcome.solution;  // the same on every rank of an MPI run
        if (!s.converged()) exit_code = exit_not_converged;
        if (!outcome.written) return;  // another rank wrote it and reports
        if (!s.qp_converged())
          std::fprintf(stderr, "dualcell-solve: warning: the solver stopped with status %s: %s (output written)\n",
                       qp::to_string(s.qp.status), s.qp.message.c_str());
        else if (!s.primal_ok)
          std::fprintf(stderr, "dualcell-solve: warning: %s (output written)\n", s.primal_message.c_str());
        if (!quiet) stage::print_solve_summary(options, outcome);
      },
      dualcell::Ranks::share);
  return status != dualcell::exit_ok ? status : exit_code;
}
