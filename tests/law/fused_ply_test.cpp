// The compact law of the whole ply (docs/method.md §16d, §16e) against what it promises by
// construction, each checked against the exact law's own evaluation of the same cell:
// - the small cell with a fuse of a cell carrying ε33 and Γ: the bonded cell in all six
//   components below its onset (stress and 6 × 6 tangent), the onset of every six-component
//   strain direction (in the plane or along z, from the kept facets alone), and past the first
//   break the cell it was given with the open shear D0z, for good;
// - the fit of a small cell's strain along the fibres (fit/small_ply.hpp): its Jacobian in
//   closed form against differences, and its error against the exact law on paths it was not
//   fitted to.
#include <gtest/gtest.h>

#include <random>

#include "fit/small_ply.hpp"
#include "law/condensed_cells.hpp"
#include "law/fused_cell.hpp"
#include "law/ply_sample.hpp"
#include "law/reduced.hpp"

namespace dualcell::law {
namespace {

// Round-off of a dense solve of a few hundred rows, relative: the fused cell and the exact law
// reach the same numbers by different algebra (its H_bb built by a QR of the facets).
constexpr double round_off = 1e-8;

struct Cells {
  CondensedCell cell, debonded;
  FusedCell fused;
};
// The off-centre glass-like cell with bonds, whole ply; past the fuse the exact debonded cell
// (its equality rows act on the c rows), so that what follows the break is exact too.
const Cells& cells() {
  static const Cells c = [] {
    Cells out;
    out.cell = testing::periodic_contact_cell(Eigen::Vector2d(0.07, -0.04), 0.02, Macro::full);
    out.debonded = debonded_cell(out.cell);
    out.fused = cell_with_fuse(out.cell, out.debonded);
    return out;
  }();
  return c;
}

CellResponse at(CellEvaluator& law, const Vector6d& e, CellHistory& h, BondMode bonds = BondMode::cascade) {
  return law.at(MacroState::ply_strain(e), h, bonds);
}

TEST(FusedPly, IsAConvexCellOfOnePairWithTheOnsetsFacetsInThePlaneAndAlongTheFibres) {
  const Cells& c = cells();
  EXPECT_EQ(consistency_problem(c.fused.cell), "");
  EXPECT_EQ(c.fused.cell.n_pairs, 1);
  EXPECT_EQ(c.fused.cell.longitudinal, 1);
  EXPECT_EQ(c.fused.cell.shear, 2);
  EXPECT_EQ(c.fused.cell.shear_rows, c.fused.facets_z);
  // Along z each pair gives two bounds (±s_t L); the polygon of Γ keeps a few of them.
  EXPECT_GE(c.fused.facets_z, 3);
  EXPECT_LT(c.fused.facets_z, c.fused.candidate_facets_z);
  EXPECT_LT(c.fused.facets, c.fused.candidate_facets);
  EXPECT_LE(c.fused.onset_error, round_off);
}

TEST(FusedPly, IsTheBondedPlyBelowItsOnsetBreaksExactlyThereAndIsTheDebondedCellAfter) {
  const Cells& c = cells();
  CellEvaluator exact(c.cell), fused(c.fused.cell), debonded(c.debonded);
  const Matrix6d S_o = open_ply_stiffness(c.cell).inverse();
  std::mt19937 rng(7);
  std::normal_distribution<double> g;
  int shear_first = 0;
  for (int i = 0; i < 100; ++i) {
    Vector6d nu;
    for (int k = 0; k < 6; ++k) nu(k) = g(rng);
    const Vector6d d = S_o * nu.normalized();
    // The onset: 1/(strength use) of the lifted cell, exact and fused.
    CellHistory le = exact.unloaded(), lf = fused.unloaded();
    const CellResponse ue = at(exact, d, le, BondMode::lifted), uf = at(fused, d, lf, BondMode::lifted);
    ASSERT_TRUE(ue.ok && uf.ok);
    ASSERT_GT(ue.strength_use, 0);
    EXPECT_NEAR(uf.strength_use / ue.strength_use, 1.0, round_off) << nu.transpose();
    const double onset = 1 / ue.strength_use;
    // Which kind of bound is reached first: the shear rows' along z or the plane's.
    double use_z = 0;
    for (Eigen::Index q = 0; q < ue.forces_z.size(); ++q)
      use_z = std::max(use_z, std::abs(ue.forces_z(q)) / c.cell.strength_z(q));
    shear_first += use_z >= ue.strength_use * (1 - 1e-12) ? 1 : 0;
    // Below the onset: the same six stresses and 6 × 6 tangent.
    CellHistory he = exact.unloaded(), hf = fused.unloaded();
    const CellResponse e = at(exact, 0.9 * onset * d, he), f = at(fused, 0.9 * onset * d, hf);
    ASSERT_TRUE(e.ok && f.ok);
    EXPECT_EQ(e.broken, 0);
    EXPECT_EQ(f.broken, 0);
    EXPECT_LE((ply_stress(f) - ply_stress(e)).norm(), round_off * ply_stress(e).norm()) << nu.transpose();
    EXPECT_LE((ply_tangent(f) - ply_tangent(e)).norm(), round_off * ply_tangent(e).norm()) << nu.transpose();
    EXPECT_NEAR(f.strength_use, 0.9, round_off);
    // Just past it the pair breaks; from then on the fused cell is the debonded one, loaded or not.
    const CellResponse past = at(fused, (1 + 1e-6) * onset * d, hf);
    ASSERT_TRUE(past.ok);
    EXPECT_EQ(past.broken, 1);
    CellHistory hd = debonded.unloaded();
    for (const double t : {1.5, 0.5, -1.0}) {
      const Vector6d s = ply_stress(at(fused, t * onset * d, hf)),
                     reference = ply_stress(at(debonded, t * onset * d, hd));
      EXPECT_LE((s - reference).norm(), round_off * reference.norm()) << nu.transpose() << " at " << t;
    }
  }
  // Both kinds of onset are met, so both kinds of facet rows are exercised.
  EXPECT_GT(shear_first, 5);
  EXPECT_LT(shear_first, 95);
}

// A small cell without adhesion (the exact law on 24 of its own solutions) given the strain
// along the fibres.
struct SmallPly {
  CondensedCell cell, small;
  std::vector<Vector6d> strain, stress;
};
const SmallPly& small_ply() {
  static const SmallPly s = [] {
    SmallPly out;
    out.cell = testing::periodic_contact_cell(Eigen::Vector2d(0.07, -0.04), 0, Macro::full);
    ReduceOptions options;
    options.tolerance = 0.02;
    options.max_rows = 24;
    out.small = reduce_cell(out.cell, sample_cell(out.cell, 300), options).cell;
    const PlySample training = sample_ply(out.cell, 120, 1);
    for (std::size_t i = 0; i < training.strain.size(); ++i)
      for (std::size_t k = 0; k < training.strain[i].size(); ++k) {
        out.strain.push_back(training.strain[i][k]);
        out.stress.push_back(training.stress[i][k]);
      }
    return out;
  }();
  return s;
}

// The residuals are piecewise linear in y33 (linear on each point's free set): central
// differences of a step that changes no free set are exact to round-off of the residuals
// (1e-16 over a step of 1e-6 of y's scale: 1e-10), asked 1e-7 of the Jacobian's largest entry.
// A point whose free set the step changes is not compared (where M_FF is nearly singular, on the
// kernel of the small cell's basis, μ moves fast with y33); they are few.
TEST(SmallPlyFit, TheJacobianInClosedFormIsTheDifferencesOfTheResiduals) {
  const SmallPly& s = small_ply();
  CondensedCell small = s.small;
  fit::SmallPlyFit fitted = fit::fit_small_ply(small, s.cell, s.strain, s.stress);
  ASSERT_TRUE(fitted.ok) << fitted.message;
  const Eigen::VectorXd y = small.y33.col(0);
  Eigen::VectorXd f, fp, fm;
  Eigen::MatrixXd J;
  ASSERT_TRUE(fit::small_ply_residuals(small, y, s.strain, s.stress, f, &J));
  const double h = 1e-6 * std::max(y.cwiseAbs().maxCoeff(), 1e-12);
  // The free set of each point at y33 = v.
  const auto free_sets = [&](const Eigen::VectorXd& v) {
    CondensedCell cell = small;
    cell.y33 = v;
    CellEvaluator law(cell);
    CellHistory history = law.unloaded();
    std::vector<std::vector<bool>> out;
    for (const Vector6d& e : s.strain) {
      const CellResponse r = at(law, e, history);
      std::vector<bool> free;
      for (Eigen::Index j = 0; j < r.forces.size(); ++j) free.push_back(r.forces(j) > 0);
      out.push_back(free);
    }
    return out;
  };
  const auto at_y = free_sets(y);
  int compared = 0, points = 0;
  for (Eigen::Index j = 0; j < y.size(); ++j) {
    Eigen::VectorXd yp = y, ym = y;
    yp(j) += h, ym(j) -= h;
    ASSERT_TRUE(fit::small_ply_residuals(small, yp, s.strain, s.stress, fp, nullptr));
    ASSERT_TRUE(fit::small_ply_residuals(small, ym, s.strain, s.stress, fm, nullptr));
    const auto at_p = free_sets(yp), at_m = free_sets(ym);
    for (std::size_t i = 0; i < s.strain.size(); ++i) {
      ++points;
      if (at_p[i] != at_y[i] || at_m[i] != at_y[i]) continue;
      ++compared;
      const Eigen::Index r = 4 * static_cast<Eigen::Index>(i);
      const Eigen::Vector4d difference = (fp.segment<4>(r) - fm.segment<4>(r)) / (2 * h);
      EXPECT_LE((difference - J.block<4, 1>(r, j)).cwiseAbs().maxCoeff(), 1e-7 * J.cwiseAbs().maxCoeff())
          << "column " << j << ", point " << i;
    }
  }
  EXPECT_GE(compared, 0.95 * points);
}

// Fitted, the strain along the fibres misses the exact law on other paths by no more than the
// small cell misses it in the plane (its rows' error, which y33 cannot remove), where y33 = 0
// (the rows blind to ε33) misses it by more.
TEST(SmallPlyFit, WithoutAdhesionItMeetsTheWholePlyOnPathsItWasNotFittedTo) {
  const SmallPly& s = small_ply();
  const PlySample check = sample_ply(s.cell, 120, 2);
  CondensedCell small = s.small;
  const fit::SmallPlyFit fitted = fit::fit_small_ply(small, s.cell, s.strain, s.stress);
  ASSERT_TRUE(fitted.ok) << fitted.message;
  EXPECT_EQ(small.shear, 2);
  EXPECT_EQ(small.shear_rows, 0);
  EXPECT_EQ(consistency_problem(small), "");
  const PlyCheck after = check_ply(small, check);
  CondensedCell blind = small;
  blind.y33.setZero();
  const PlyCheck before = check_ply(blind, check);
  const ConeCheck in_plane = check_reduced(s.small, sample_cell(s.cell, 400));
  // Measured: 3.5 % in the plane; 2.4 % fitted (1.7 % on its training points), 6.2 % blind.
  EXPECT_EQ(after.directions, 120);
  EXPECT_LE(after.max_error, in_plane.max_error);
  EXPECT_LT(after.max_error, before.max_error);
  EXPECT_LE(fitted.training_max_error, in_plane.max_error);
}

}  // namespace
}  // namespace dualcell::law
