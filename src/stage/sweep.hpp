#pragma once
// The sweep stage as one call (dualcell-sweep): every path of the scene through one solver
// (setup once for the whole sweep), each finished path journaled at once in <out>.parts/ so that
// an interrupted run, even by kill -9, resumes where it stopped and ends with the same sweep.h5;
// progress with the time left on stderr (core/progress.hpp). Under mpirun the paths are handed out
// to the ranks (or groups of ranks_per_path ranks) as they ask for them, and rank 0 writes
// sweep.h5 (docs/method.md §16).
#include <string>

#include "fit/fit.hpp"

namespace dualcell::stage {

struct SweepOptions {
  std::string scene_file, mesh_file, out;
  int threads = 0;  // 0 = all OpenMP offers; results do not depend on it
  // Under mpirun: the ranks that solve one path together, sharing its subdomains (a path too
  // large for one rank); the groups take paths as single ranks do. Results do not depend on it.
  int ranks_per_path = 1;
  bool progress = false;     // progress line on stderr
  long interrupt_after = 0;  // tests of the resume: the last rank SIGKILLs itself after this many computed paths
  // The exact law's rows above which the fit does not sample it (fit::max_checked_rows; tests
  // lower both). Above them, or where the cell has no exact law, a scene without adhesion and with
  // sphere paths gets the cell on a basis of its own solutions (/cell_basis, docs/method.md §16c):
  // the small cell's start, fitted to the sphere paths' full solves.
  int sampled_rows = fit::max_checked_rows;
};

struct SweepSummary {
  bool written = false;  // this rank wrote sweep.h5 (rank 0; the only one without MPI)
  int paths = 0, resumed = 0, fuses = 0, unconverged_steps = 0;
  double seconds = 0;
  // The exact law condensed from the sweep's factorisation (/cell): its interface rows, bytes and
  // seconds; or why there is none.
  int cell_rows = 0;
  double cell_bytes = 0, cell_seconds = 0;
  std::string cell_note;
  // The cell on a basis of its own solutions (/cell_basis): its rows (0: none) and seconds, with
  // its solves.
  int basis_rows = 0;
  double basis_seconds = 0;
  // The scene's [solver] dual_operator and how many of the subdomains it made explicit for this
  // sweep (the solver of rank 0's group).
  std::string dual_operator;
  int subdomains = 0, explicit_subdomains = 0;
};

SweepSummary run_sweep(const SweepOptions& options);

}  // namespace dualcell::stage
