// The exact law on a basis of its own solutions (law/reduced.hpp) against what holds whatever
// the basis: its feasible set is part of the cell's, so it is never stiffer than the cell
// (σ·ε_reduced(σ) ≥ σ·ε_cell(σ) at every stress), it is exact along every direction whose solution
// is a column, and it is a cell the exact law's checks accept (convex). The greedy stops at its
// tolerance on its training directions, and another sample of directions measures it.
#include "law/reduced.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>

#include "law/condensed_cells.hpp"

namespace dualcell::law {
namespace {

TEST(ReducedCell, IsNeverStifferThanTheCellAndExactAtItsColumns) {
  const CondensedCell cell = testing::periodic_contact_cell(Eigen::Vector2d(0.07, -0.04));
  const CellSample training = sample_cell(cell, 200);
  ReduceOptions options;
  options.tolerance = 0.05;
  const ReducedCell reduced = reduce_cell(cell, training, options);
  ASSERT_TRUE(reduced.ok) << reduced.message;
  const int m = reduced.cell.n_rows();
  EXPECT_GT(m, 0);
  EXPECT_EQ(consistency_problem(reduced.cell), "");
  // The columns are the cell's solutions: nonnegative and in equilibrium with the fibre.
  EXPECT_GE(reduced.basis.minCoeff(), 0.0);
  EXPECT_LE((cell.G * reduced.basis).cwiseAbs().maxCoeff(), 1e-9 * cell.G.cwiseAbs().maxCoeff());

  CellEvaluator exact(cell), small(reduced.cell);
  CellHistory he = exact.unloaded(), hs = small.unloaded();
  // Exact along each chosen direction, whatever the load (homogeneous): to the compliance the
  // basis adds per row (1e-9 of H_r's largest entry) times the conditioning of the active rows.
  for (const Eigen::Vector3d& N : reduced.directions)
    for (const double s : {0.5, 2.0}) {
      const Eigen::Vector3d e = exact.at_stress(s * N, he).strain, r = small.at_stress(s * N, hs).strain;
      EXPECT_LE((r - e).norm(), 1e-6 * e.norm()) << N.transpose();
    }
  // Never stiffer, at random stresses: the reduced problem maximises over a subset.
  std::mt19937 rng(11);
  std::normal_distribution<double> g;
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d sigma(g(rng), g(rng), g(rng));
    const double work_exact = sigma.dot(exact.at_stress(sigma, he).strain);
    const double work_small = sigma.dot(small.at_stress(sigma, hs).strain);
    EXPECT_GE(work_small, work_exact * (1 - 1e-9)) << sigma.transpose();
  }
  // The greedy's own record ends within its tolerance, and another sample measures it: a
  // reduction that only fits its training directions would show here (bound 2× the tolerance:
  // the check's directions lie between the training ones).
  EXPECT_LE(reduced.training_max_error.back(), options.tolerance);
  const ConeCheck check = check_reduced(reduced.cell, sample_cell(cell, 300));
  EXPECT_LE(check.max_error, 2 * options.tolerance);
}

TEST(ReducedCell, RefusesACellWithAdhesion) {
  const CondensedCell cell = testing::periodic_contact_cell(Eigen::Vector2d(0.07, -0.04), 0.02);
  const ReducedCell reduced = reduce_cell(cell, sample_cell(cell, 50));
  EXPECT_FALSE(reduced.ok);
  EXPECT_NE(reduced.message.find("adhesion"), std::string::npos) << reduced.message;
}

}  // namespace
}  // namespace dualcell::law
