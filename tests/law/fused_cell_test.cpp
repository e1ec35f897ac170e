// The compact law of a cell with adhesion (law/fused_cell.hpp) against what it promises by
// construction: the bonded cell exactly below the onset (strain, stress and tangent), the exact
// onset along every direction (from the kept facets alone), and past the first break the cell it
// was given, for good. Each is checked against the exact law's own evaluation of the same cell.
#include "law/fused_cell.hpp"

#include <gtest/gtest.h>

#include <random>

#include "law/condensed_cells.hpp"
#include "law/reduced.hpp"

namespace dualcell::law {
namespace {

// Round-off of a dense solve of a few hundred rows, relative: the fused cell and the exact law
// reach the same numbers by different algebra (its H_bb built by a QR of the facets).
constexpr double round_off = 1e-8;

struct Cells {
  CondensedCell cell, after;
  FusedCell fused;
};
const Cells& cells() {
  static const Cells c = [] {
    Cells out;
    out.cell = testing::periodic_contact_cell(Eigen::Vector2d(0.07, -0.04), 0.02);
    const CondensedCell debonded = debonded_cell(out.cell);
    ReduceOptions options;
    options.tolerance = 0.05;
    const ReducedCell reduced = reduce_cell(debonded, sample_cell(debonded, 200), options);
    EXPECT_TRUE(reduced.ok) << reduced.message;
    out.after = reduced.cell;
    out.fused = cell_with_fuse(out.cell, out.after);
    return out;
  }();
  return c;
}

std::vector<Eigen::Vector3d> random_directions(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g;
  std::vector<Eigen::Vector3d> out;
  for (int i = 0; i < n; ++i) out.push_back(Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized());
  return out;
}

TEST(FusedCell, IsAConvexCellOfOnePairWithTheOnsetsFacetsOnly) {
  const Cells& c = cells();
  EXPECT_EQ(consistency_problem(c.fused.cell), "");
  EXPECT_EQ(c.fused.cell.n_pairs, 1);
  EXPECT_EQ(c.fused.cell.n_rows(), c.fused.facets + c.after.n_rows());
  // The cell's bonds have strength bounds behind others (never reached first): dropped, and the
  // onset of the kept ones equals that of all of them to round-off.
  EXPECT_GT(c.fused.facets, 0);
  EXPECT_LT(c.fused.facets, c.fused.candidate_facets);
  EXPECT_LE(c.fused.onset_error, round_off);
}

TEST(FusedCell, IsTheBondedCellBelowItsOnsetAndBreaksExactlyThere) {
  const Cells& c = cells();
  CellEvaluator exact(c.cell), fused(c.fused.cell);
  int finite = 0;
  for (const Eigen::Vector3d& N : random_directions(200, 5)) {
    const double s_exact = exact.onset(N), s_fused = fused.onset(N);
    if (!std::isfinite(s_exact)) {
      EXPECT_FALSE(std::isfinite(s_fused)) << N.transpose();
      continue;
    }
    ++finite;
    EXPECT_NEAR(s_fused / s_exact, 1.0, round_off) << N.transpose();
    // Below the onset: the same strain, and strain-driven the same stress and tangent.
    CellHistory he = exact.unloaded(), hf = fused.unloaded();
    const CellResponse e = exact.at_stress(0.9 * s_exact * N, he), f = fused.at_stress(0.9 * s_exact * N, hf);
    ASSERT_TRUE(e.ok && f.ok);
    EXPECT_EQ(f.broken, 0);
    EXPECT_LE((f.strain - e.strain).norm(), round_off * e.strain.norm()) << N.transpose();
    const CellResponse es = exact.at_strain(e.strain, he), fs = fused.at_strain(e.strain, hf);
    EXPECT_LE((fs.stress - es.stress).norm(), round_off * es.stress.norm()) << N.transpose();
    EXPECT_LE((fs.tangent - es.tangent).norm(), round_off * es.tangent.norm()) << N.transpose();
    // Its strength use is the onset measure: 0.9 of the way.
    EXPECT_NEAR(f.strength_use, 0.9, round_off);
    // Just past the onset the pair breaks, and from then on the cell is `after`, unloaded or not.
    const CellResponse past = fused.at_stress((1 + 1e-6) * s_exact * N, hf);
    ASSERT_TRUE(past.ok);
    EXPECT_EQ(past.broken, 1);
    CellEvaluator after(c.after);
    CellHistory ha = after.unloaded();
    for (const double s : {1.5, 0.5, -1.0}) {
      const Eigen::Vector3d strain = fused.at_stress(s * s_exact * N, hf).strain;
      const Eigen::Vector3d reference = after.at_stress(s * s_exact * N, ha).strain;
      EXPECT_LE((strain - reference).norm(), round_off * reference.norm()) << N.transpose() << " at " << s;
    }
  }
  EXPECT_GT(finite, 100);  // the glass-like cell's bonds break along most directions
}

TEST(FusedCell, AlongTheCascadePathsItsErrorIncludesTheLastPoint) {
  // With the fully debonded exact cell past the fuse, the only error is that the cascade leaves
  // some bonds intact: at the last point of each path it is the debonded cell's miss there
  // (check_reduced of that cell), and along the path at least that.
  const Cells& c = cells();
  const CondensedCell debonded = debonded_cell(c.cell);
  const FusedCell fused = cell_with_fuse(c.cell, debonded);
  EXPECT_EQ(consistency_problem(fused.cell), "");
  const CellSample past = sample_cell_past_fuse(c.cell, 60, past_fuse_load_ratio);
  const ConeCheck along = check_along_fuse_paths(fused.cell, past), last = check_reduced(debonded, past);
  ASSERT_EQ(along.error.size(), last.error.size());
  int counted = 0;
  for (std::size_t i = 0; i < along.error.size(); ++i) {
    if (std::isnan(last.error[i])) continue;
    ++counted;
    EXPECT_EQ(past.path_strain[i].size(), static_cast<std::size_t>(past_fuse_steps));
    EXPECT_GE(along.error[i], last.error[i] - round_off) << past.direction[i].transpose();
  }
  EXPECT_GT(counted, 30);
  EXPECT_GE(along.max_error, last.max_error - round_off);
}

TEST(FusedCell, RefusesACellWithoutAdhesionAndAForeignCellPastTheFuse) {
  const Cells& c = cells();
  EXPECT_THROW(cell_with_fuse(c.after, c.after), std::invalid_argument);  // no adhesion
  CondensedCell other = c.after;
  other.S0 *= 2;
  EXPECT_THROW(cell_with_fuse(c.cell, other), std::invalid_argument);
  EXPECT_THROW(cell_with_fuse(c.cell, c.cell), std::invalid_argument);  // with adhesion
}

}  // namespace
}  // namespace dualcell::law
