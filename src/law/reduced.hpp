#pragma once
// The compact law as a small cell (docs/method.md §16c): the exact law (law/condensed.hpp) with
// its interface forces restricted to nonnegative combinations of a few of its own solutions.
//
//   symbol | variable       | meaning
//   -------+----------------+-------------------------------------------------------------
//   V      | basis (n × m)  | columns v_j = p*(N_j)/‖p*(N_j)‖∞: the exact law's interface forces
//          |                | at the stress directions N_j the greedy chose
//   μ      | the rows' p    | the reduced cell's forces: p = V μ, μ ≥ 0
//
// Without adhesion every exact solution p* is nonnegative and in equilibrium with every fibre
// (G p* = 0), so p = Vμ with μ ≥ 0 is admissible for the cell whatever μ: the reduced cell is
//   H_r = Vᵀ H V,  Y_r = Vᵀ Y,  S₀ and |Ω| the cell's,  no equality rows,  0 ≤ μ,
// a CondensedCell of m rows that every evaluator of the exact law takes as it is. Its feasible
// set is a subset of the cell's, so its complementary energy bounds the cell's from above, the
// bound can only tighten as columns are added, and it is exact (to round-off) along every N_j,
// and on every cone of stresses whose extreme rays' solutions are all columns (p* is linear on
// each cone of the exact law's pieces).
#include <Eigen/Core>
#include <string>
#include <vector>

#include "law/condensed.hpp"
#include "law/cone_check.hpp"

namespace dualcell::law {

// A cell of m rows with the macro part (n_macro, |Ω|, S₀) of `cell`: Y (m × n_macro) and H
// (m × m) given, no equality rows, each row a contact row (0 ≤ μ, no bond).
CondensedCell cell_of_rows(const CondensedCell& cell, const Eigen::MatrixXd& Y, const Eigen::MatrixXd& H);

// The cell restricted to p = Vμ, μ ≥ 0 (V's columns nonnegative and in equilibrium: G V ≈ 0).
CondensedCell cell_on_basis(const CondensedCell& cell, const Eigen::MatrixXd& V);

// The compliance cell_on_basis adds to every row, relative to H_r's largest diagonal entry.
inline constexpr double basis_compliance = 1e-9;
// VᵀHV with that compliance on its diagonal (none for no columns).
Eigen::MatrixXd with_basis_compliance(Eigen::MatrixXd VtHV);

struct ReduceOptions {
  double tolerance = 0.02;    // the largest relative stress error over the training directions
  int max_rows = 64;          // m at most
  bool split_by_body = true;  // each snapshot split into its parts on each fibre
};

struct ReducedCell {
  bool ok = false;                          // the training error reached the tolerance within max_rows
  std::string message;                      // why not, when not ok
  CondensedCell cell;                       // the reduced cell (m rows), also when not ok: the best reached
  Eigen::MatrixXd basis;                    // V (n × m): the cell's forces of the reduced cell's μ are V μ
  std::vector<Eigen::Vector3d> directions;  // N_j of each row's snapshot, in the order chosen
  std::vector<double> training_max_error;   // after 0, 1, …, m rows, over the training sample
  double seconds = 0;
};

// The greedy: from the open cell (no rows), add the snapshot p* at the training direction of
// the largest error until that error is at most options.tolerance. The training sample is the
// exact law's (sample_cell, with forces) at directions other than the check's. Refused (not ok,
// message) for a cell with adhesion: its bonded rows carry tension, so Vμ with μ ≥ 0 is not
// its admissible set.
ReducedCell reduce_cell(const CondensedCell& cell, const CellSample& training, const ReduceOptions& options = {});

// The reduced cell against the exact law's sample (the check's directions): check_law with the
// reduced cell's stress at the exact strain, from the bonds as they are (no break).
ConeCheck check_reduced(const CondensedCell& reduced, const CellSample& sample);

}  // namespace dualcell::law
