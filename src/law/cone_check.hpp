#pragma once
// The compact law measured against the exact one (docs/method.md §16a): the cone-wise law fitted
// to the sweep (law/cone.hpp) and the cell condensed onto its interface rows (law/condensed.hpp)
// at directions no sweep needs to have contained, as many as the exact law makes cheap.
//
// Per unit macro stress N of a dense set (the sphere of (σxx, σyy, √2σxy), or the circle of
// (σxx, σyy) for a cell without shear), at the load s = 1 without adhesion (both laws are
// homogeneous) and s = ½ s*(N) with it (below the exact onset: bonded): the exact strain
// ε = ε_cell(sN), the compact law's stress σ_cone(ε) there, and the relative stress error
// ‖σ_cone(ε) − sN‖ / s — what a structure code with the compact law gets wrong at a strain the
// cell really takes.
#include <Eigen/Core>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "core/progress.hpp"
#include "law/condensed.hpp"
#include "law/cone.hpp"
#include "law/polar.hpp"

namespace dualcell::law {

// What a compact law was measured against: the exact law at a dense set of directions, or,
// where the cell has no exact law (law::Law::cell_note says why), the sweep's own points, each
// uniaxial direction held out of the fit in turn and the law fitted without it evaluated there.
// Or, where the exact law is too large to sample, full solves of the cell along the sphere paths
// that neither law was fitted to (docs/method.md §16c). Or, for the small cell of a cell with
// adhesion, the exact law along its cascade paths past the fuse (docs/method.md §16d).
enum class CheckedAgainst { exact_law, held_out_directions, held_out_solves, exact_law_past_fuse };
// "the exact law" / "held-out sweep directions" / "held-out full solves" / "the exact law past
// the fuse": for summaries, refusals and law.h5.
const char* checked_against_text(CheckedAgainst against);
CheckedAgainst checked_against_from(const std::string& text);  // throws std::invalid_argument

struct ConeCheck {
  CheckedAgainst against = CheckedAgainst::exact_law;
  std::vector<Eigen::Vector3d> directions;  // the unit stress directions N, in the order evaluated
  std::vector<double> error;                // per direction
  double max_error = 0, rms_error = 0;
  Eigen::Vector3d worst = Eigen::Vector3d::Zero();  // the N of max_error
  // The same for the law fitted to the sweep's points (fit/cone_fit.hpp, fit_cone), measured on the
  // same directions, whichever law was kept (NaN where there was none).
  double sweep_fit_max_error = std::numeric_limits<double>::quiet_NaN();
  double sweep_fit_rms_error = std::numeric_limits<double>::quiet_NaN();
  // Against the exact law: the exact law's apparent moduli around the circle (exact_polar).
  PolarModuli polar;
};

// The unit stress directions of a sample of about n: along rings on the sphere of (σxx, σyy,
// √2σxy) for n_macro = 3, on the circle of (σxx, σyy) (n/2, at least 180) for n_macro = 2,
// consecutive directions neighbours. Two samples share no direction where one has an odd count
// of rings (of directions on the circle) and the other an even one.
std::vector<Eigen::Vector3d> sample_directions(int n_macro, int n);

// The exact law sampled at about `n` unit stress directions N (n on the sphere of (σxx, σyy,
// √2σxy); n/2, at least 180, on the circle of (σxx, σyy) for a cell without shear), ordered
// along rings so that each evaluation warm-starts from its neighbour, at the load s = 1 (½ s*(N)
// with adhesion): the points (ε, σ = sN), each from the intact cell. A direction whose
// evaluation fails or breaks a bond has a NaN strain.
struct CellSample {
  std::vector<Eigen::Vector3d> direction, strain, stress;
  std::vector<Eigen::VectorXd> forces;  // p at each point (empty where the strain is NaN)
  // sample_cell_past_fuse only: per direction the points of its path before the last (just past
  // the onset, then each step), strain and stress (empty where the strain is NaN).
  std::vector<std::vector<Eigen::Vector3d>> path_strain, path_stress;
};
// `progress`: where a long sample says how far it is (none by default).
CellSample sample_cell(const CondensedCell& cell, int n, Progress* progress = nullptr);

// The exact law past the fuse, for the compact law after it (Law::cone_after_fuse): the same
// directions N, each loaded from the intact cell just past its onset s*(N) (the cascade) and
// then in past_fuse_steps steps to `factor`·s*(N), with its history. NaN where the cell has no
// onset along N or an evaluation fails.
// The load of that check over the onset: past the cascade, within the loads a sweep carries
// past its fuse.
inline constexpr double past_fuse_load_ratio = 2;
// Steps from the onset to it: along a path a bond can pass its strength on the way and not at the
// end, so one step would miss breaks (0.8 % of strain at some directions of a test cell; four
// steps already give the path of forty there).
inline constexpr int past_fuse_steps = 8;
CellSample sample_cell_past_fuse(const CondensedCell& cell, int n, double factor, Progress* progress = nullptr);

// The one walk of the samplers (sample_cell_past_fuse here, sample_ply for the whole ply): the
// exact law at state_at(t) for each load factor t of `loads` in turn, the history carried from
// point to point; it stops at the first evaluation that fails (the last response, not ok).
std::vector<CellResponse> walk_path(CellEvaluator& evaluator, CellHistory& history, const std::vector<double>& loads,
                                    const std::function<MacroState(double)>& state_at);
// The load factors of a path past the onset, over the onset: just past it (the first break and
// its cascade), then past_fuse_steps equal steps to `factor`.
std::vector<double> past_onset_factors(double factor);

// The check over a sample of the exact law (sample_cell) of any compact law, given as its stress at
// a strain (NaN where it has none); polar_* are left empty.
ConeCheck check_law(const std::function<Eigen::Vector3d(const Eigen::Vector3d&)>& stress_at, const CellSample& sample);
// The one check over a sample: error_at(i), the relative error at direction i (non-finite: the
// law has no answer, the worst), for each direction where the sample has a point of the exact
// law; NaN where it has none (not counted).
ConeCheck check_over(const CellSample& sample, const std::function<double(std::size_t)>& error_at);
// check_law of the cone-wise law.
ConeCheck check_cone(const ConeLaw& cone, const CellSample& sample);
// The exact law's apparent moduli around the circle (polar_moduli), each from the intact cell at
// the load s = 1 (½ s*(N) with adhesion, so that no bond breaks); NaN where an evaluation fails.
PolarModuli exact_polar(const CondensedCell& cell);

}  // namespace dualcell::law
