#pragma once
// The solve stage as one call (dualcell-solve): one macro stress σ̄ through the scene's boundary
// condition, from a given bond state, written to solution.h5 (+ XDMF); and its summary. With
// `[load] boundary = "edges"` the block is a structure of resolved cells: its load steps (the
// scene's [steps] factors) are solved in order with the bond history carried from one to the
// next, and the last step's solution is written with a /steps table.
#include <Eigen/Core>
#include <optional>
#include <string>

#include "feti/solver.hpp"
#include "io/solution_file.hpp"

namespace dualcell::stage {

struct SolveOptions {
  std::string scene_file, mesh_file, out;
  std::string stress_text;          // "sxx,syy,sxy" as given on the command line; empty with boundary = "edges"
  std::string bonds_file;           // a solution.h5 whose bond state is the start; empty: intact
  double eps33 = 0;                 // longitudinal strain ε33 (generalised plane strain); 0: plane strain
  bool longitudinal_shear = false;  // also the cell's longitudinal shear moduli in the solution's bond state
  bool onset = false;               // also the debond onset factor along the stress (feti::debond_onset)
  int threads = 0;
  bool progress = true;  // phases, QP iterations and load steps on stderr (rank 0); --quiet: none
};

struct SolveOutcome {
  Scene scene;
  // With SolveOptions::longitudinal_shear: G of ⟨τ⟩ = G Γ (τxz, τyz against γxz, γyz) with the
  // interface pairs bonded as the solution left them (none without adhesion: frictionless contact
  // carries no shear along z).
  std::optional<Eigen::Matrix2d> longitudinal_shear;
  int dim_u = 0, threads_used = 1;
  feti::Solution solution;  // the last step's with boundary = "edges"
  // With the scene's temperature change ΔT: the cool-down (ΔT alone, σ̄ = 0) is solved first, with
  // contact and bonds, and the load starts from its bond state; the pairs it broke.
  std::optional<long> cool_down_broken;
  // With SolveOptions::onset: s* along the stress, from the intact interface (and the cool-down).
  std::optional<double> onset;
  std::string onset_note;              // why the onset is NaN (feti::ContactSolver::onset_note)
  std::optional<io::LoadSteps> steps;  // boundary = "edges" only
  io::RankTable ranks;                 // one entry per rank that shared the solve
  bool written = false;                // this rank wrote the output (rank 0)
};

// "0.01,0,-2e-3" → (σxx, σyy, σxy); anything else is an InputError quoting `text`.
Eigen::Vector3d parse_stress(const std::string& text);

// Under mpirun every rank runs this together: the subdomains are shared out over the ranks
// (feti::FetiSetup), every rank gets the whole solution, and rank 0 writes it.
SolveOutcome run_solve(const SolveOptions& options);
// The one-screen summary: status, iterations, macro strain, Hill–Mandel, KKT, seconds per phase.
void print_solve_summary(const SolveOptions& options, const SolveOutcome& outcome);

}  // namespace dualcell::stage
