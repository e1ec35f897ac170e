#pragma once
// Load paths in magnitude and direction (docs/method.md §13). A path is a unit macro
// stress N (uniaxial n⊗n with n = (cos θ, sin θ), or a general tensor) and a sign; its steps
// follow the scene's magnitudes of that sign in increasing size, carry the bond state (breaks
// are irreversible) and warm-start from the previous multipliers scaled to the new load.
// Tension and compression each start from the unloaded, intact state. A path of [sweep] eps33
// holds that strain along the fibres from its start (generalised plane strain, §3a): its loads
// are the in-plane stress's, its steps record σ33, and it has no exact onset (the load is not
// linear in its factor then), so its jumps are bracketed by bisection alone. A path of [sweep]
// gamma holds those shears along the fibres likewise (the antiplane solve beside each QP, its
// ties breaking with the bonds: the macro state's Γ in feti::ContactSolver::solve); its steps record
// ⟨τ⟩, and its first step is the shear alone (load 0), so that the bonds it breaks by itself are
// a state of the path, as the exact law's replay meets them.
//
// The fuse: with adhesion, the exact debond onset s* (docs/method.md §11) is inserted as a step, and
// wherever new breaks appear between two steps the load is bisected until the jump is
// bracketed within fuse_tolerance·load; the states just before and after are recorded.
#include <Eigen/Core>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "core/provenance.hpp"
#include "core/scene.hpp"
#include "feti/solver.hpp"
#include "law/condensed.hpp"

namespace dualcell::sweep {

struct PathSpec {
  int index = 0;
  double direction_deg = 0;  // NaN for a general stress direction
  int sign = 1;              // +1 tension, −1 compression
  // The path's macro state at load factor 1 (core/macro_state.hpp): its in-plane stress N
  // (σxx, σyy, σxy), unit Frobenius norm, and what it holds along the fibres, the strain ε33
  // ([sweep] eps33) or the shears Γ ([sweep] gamma), and the scene's temperature change ΔT
  // ([load] delta_T, every path). At load s the state is state.at_factor(s): σ̄ = s·N with the held
  // part unchanged.
  MacroState state;
  std::vector<double> loads;  // signed loads s, |s| increasing
  bool sphere = false;        // one of [sweep] sphere's directions (sign +1, direction_deg NaN)
  // Nothing held along the fibres (ε33, Γ); the scene's ΔT, which every path holds, does not count
  // (the onset from the cool-down is affine, feti::ContactSolver::debond_onset).
  bool in_plane() const { return (state.nonzero() & (MacroState::along_mask | MacroState::shear_mask)) == 0; }
};

// The N directions of [sweep] sphere: a Fibonacci point set on the unit sphere of
// (σxx, σyy, √2σxy), returned as stress tensors (σxx, σyy, σxy) of unit Frobenius norm.
std::vector<Eigen::Vector3d> sphere_directions(int n);

struct Step {
  double load = 0;
  Eigen::Vector3d stress = Eigen::Vector3d::Zero();
  Eigen::Vector3d strain = Eigen::Vector3d::Zero();  // tensor shear
  long broken_bonds = 0;                             // broken so far along the path
  long outer_iterations = 0;
  long operator_applications = 0;
  double kkt_residual = 0;  // max of the relative projected gradient, ‖Gλ−e‖ and equilibrium residuals
  // σ33 (the average σzz) of a path with a strain along the fibres; NaN on a plane-strain path.
  double stress_zz = std::numeric_limits<double>::quiet_NaN();
  // ⟨τ⟩ = (τxz, τyz) of a path with shears along the fibres; NaN otherwise.
  Eigen::Vector2d shear_stress = Eigen::Vector2d::Constant(std::numeric_limits<double>::quiet_NaN());
  double seconds = 0;
  bool converged = true;
};

// One check of the strain along the fibres (a scene's [load] macro = "full"): the full solve of
// generalised plane strain at the macro stress σ̄ (tensor shear) and ε33, and what it gave, ε̄
// (tensor shear, as Step) and σ33. The fit replays them through the exact law (docs/method.md §16a).
struct LongitudinalPoint {
  Eigen::Vector3d stress = Eigen::Vector3d::Zero();
  double eps33 = 0;
  Eigen::Vector3d strain = Eigen::Vector3d::Zero();
  double stress_zz = 0;
  // The pairs the solve broke (its debond loop from the intact cell: the points past the fuse);
  // 0 for the points far below any strength, solved with the bonds held.
  long broken = 0;
};

// One check of the shear along the fibres (a full periodic cell): the one-body antiplane solve at
// Γ = (γxz, γyz) along a path of growing Γ from the intact cell, its ties' debond cascade run to
// the end at each point (primal::longitudinal_shear_at and the bond rule), and what it gave: ⟨τ⟩
// and the pairs broken. The fit replays each path through the exact law (docs/method.md §16a).
struct ShearPoint {
  int path = 0;
  Eigen::Vector2d gamma = Eigen::Vector2d::Zero();
  Eigen::Vector2d tau = Eigen::Vector2d::Zero();
  int broken = 0;
};

// The largest jump along a path: the bracket whose strain along the load (N:ε) grows most.
struct Fuse {
  double onset_load = 0;   // predicted s* (signed): the first bond reaches its strength
  double load_before = 0;  // largest bracketed load without the jump
  double load_after = 0;   // smallest bracketed load with it
  Eigen::Vector3d strain_before = Eigen::Vector3d::Zero();
  Eigen::Vector3d strain_after = Eigen::Vector3d::Zero();
};

// What a sweep records besides its paths: where it came from, the constituents, and the cell's
// exact debond onset surface. The fit reads it with the paths; io writes and reads it
// (io/sweep_file.hpp, which also derives the key that identifies a run's inputs).
struct SweepHeader {
  Provenance provenance;      // scene, material, mesh, solver options, code version
  Constituents constituents;  // fibre_E, ..., fibre_volume_fraction
  law::OnsetSurface onset;    // the cell's exact debond onset surface
  // The cell condensed onto its interface rows (docs/method.md §16a), built once by the sweep from
  // its factorisation; none (and cell_note says why) where the scene has no cell law or the
  // dense condensation would not pay.
  std::optional<law::CondensedCell> cell;
  std::string cell_note;
  // The cell on a basis of its own solutions (docs/method.md §16c), built where the exact law is
  // too large for the fit to sample (stage::SweepOptions::sampled_rows): the small cell's start,
  // whose rows the fit fits to the sphere paths; none (and cell_basis_note says why, where it was
  // tried) otherwise.
  std::optional<law::CondensedCell> cell_basis;
  std::string cell_basis_note;
  // Where the exact law carries the strain along the fibres: its checks against the full solve.
  std::vector<LongitudinalPoint> longitudinal_points;
  // Where it carries the shears along the fibres: its checks against the one-body solve.
  std::vector<ShearPoint> shear_points;
  // The bonded cell's thermal expansion, where both phases have theirs (/expansion).
  law::PlyExpansion expansion;
  // The scene's temperature change, held along every path (root attribute delta_T where ≠ 0).
  double delta_T = 0;
  double qp_tolerance = std::numeric_limits<double>::quiet_NaN();  // [solver] tolerance of the paths' QPs
};

struct PathResult {
  PathSpec spec;
  std::vector<Step> steps;
  std::optional<Fuse> fuse;
};

// The paths of a scene, in file order: per direction θ, tension then compression (where the
// magnitudes have that sign), then the general stress directions likewise. Throws InputError
// for a direction the boundary condition cannot carry (symmetry: shear-free only).
std::vector<PathSpec> plan_paths(const Scene& scene);

// A walk along the load factor t of a macro state (core/macro_state.hpp: its in-plane stress
// t·N, with what it holds along the fibres) from a bond state: each solve starts from the last
// accepted state's bonds (breaks are irreversible) and warm-starts from its λ and SMALBE
// multiplier scaled to the new load (exact for a positively homogeneous step, so a proportional
// step costs almost nothing). The sweep's paths and the load steps of a resolved structure walk
// this way.
class LoadWalk {
 public:
  LoadWalk(feti::ContactSolver& solver, const MacroState& direction, feti::BondState bonds)
      : solver_(solver), direction_(direction), bonds_(std::move(bonds)) {}
  // The solve at `load` from the last accepted state, or from `from` (the accepted bonds with
  // some more broken) when given.
  feti::Solution solve(double load, const feti::BondState* from = nullptr);
  // Makes s, the solution at `load`, the state the next solves start from.
  void accept(double load, const feti::Solution& s);
  const feti::BondState& bonds() const { return bonds_; }
  double load() const { return load_; }

 private:
  feti::ContactSolver& solver_;
  MacroState direction_;
  feti::BondState bonds_;
  Eigen::VectorXd lambda_, multiplier_;
  double load_ = 0;
};

// Bonds intact in `intact` and broken in `now`.
int count_broken(const feti::BondState& intact, const feti::BondState& now);

// Called after every recorded step (both sides of a fuse bracket; not the bisection's inner
// solves): the path, the step's index, the step.
using StepObserver = std::function<void(const PathSpec&, int step, const Step&)>;

// Runs one path from the intact, unloaded state. Deterministic: the same solver and spec give
// the same numbers whatever ran before.
PathResult run_path(feti::ContactSolver& solver, const PathSpec& spec, double fuse_tolerance,
                    const StepObserver& on_step = {});

}  // namespace dualcell::sweep
