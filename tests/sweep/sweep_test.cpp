// Load paths: linearity without adhesion, bimodularity, directional symmetry, the bonded
// response below the onset, and the fuse (docs/method.md §11, §13).
#include "sweep/sweep.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "core/error.hpp"
#include "feti/solver.hpp"
#include "test_util.hpp"

namespace dualcell::sweep {
namespace {

Scene make_scene(int cells, int degree, double radius, Boundary boundary, double Ef, double Em, double strength,
                 std::vector<double> directions, std::vector<double> magnitudes, Element element = Element::p1) {
  Scene s = parse_scene(testing::scene_text(cells, cells, degree, radius), "test.toml");
  s.geometry.element = element;
  s.fibre = {Ef, 0.2};
  s.matrix = {Em, 0.35};
  s.load.boundary = boundary;
  s.interface = {strength, strength};
  s.sweep.directions_deg = std::move(directions);
  s.sweep.magnitudes = std::move(magnitudes);
  s.solver.tolerance = 1e-9;
  return s;
}

// Apparent modulus along the load: s / (N:ε).
double modulus(const PathSpec& spec, const Step& step) {
  const Eigen::Vector3d N = spec.state.in_plane();
  return step.load / (N(0) * step.strain(0) + N(1) * step.strain(1) + 2 * N(2) * step.strain(2));
}

TEST(Sweep, PlansPathsAndRefusesDirectionsTheBoundaryCannotCarry) {
  Scene s = make_scene(1, 1, 0.3, Boundary::traction, 10, 1, 0, {0, 45}, {-2, 1, -1, 2});
  s.sweep.stress_directions = {{1, 1, 0}};
  const auto paths = plan_paths(s);
  ASSERT_EQ(paths.size(), 6u);
  EXPECT_EQ(paths[0].sign, 1);
  EXPECT_EQ(paths[0].loads, (std::vector<double>{1, 2}));
  EXPECT_EQ(paths[1].loads, (std::vector<double>{-1, -2}));
  EXPECT_NEAR(paths[2].state.in_plane()(2), 0.5, 1e-15);  // 45°: n⊗n = [[1/2, 1/2], [1/2, 1/2]]
  EXPECT_NEAR(paths[4].state.in_plane()(0), std::sqrt(0.5), 1e-15);
  EXPECT_TRUE(std::isnan(paths[4].direction_deg));
  s.load.boundary = Boundary::symmetry;
  try {
    plan_paths(s);
    FAIL() << "45° accepted with the symmetry boundary";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("directions_deg contains 45"), std::string::npos) << e.what();
  }
  s.sweep.directions_deg = {0, 90, 180};
  s.sweep.stress_directions.clear();
  EXPECT_EQ(plan_paths(s).size(), 6u);
}

class SweepOrders : public ::testing::TestWithParam<Element> {};
INSTANTIATE_TEST_SUITE_P(Order, SweepOrders, ::testing::Values(Element::p1, Element::p2),
                         [](const auto& info) { return std::string(to_string(info.param)); });

TEST_P(SweepOrders, WithoutAdhesionLinearBimodularAndDirectional) {
  const Scene scene = make_scene(1, 2, 0.35, Boundary::traction, 100, 1, 0, {0, 45, 90}, {-2, -1, 1, 2, 3}, GetParam());
  const mesh::Mesh m = mesh::build_mesh(scene.geometry);
  feti::ContactSolver solver(m, scene);
  std::vector<PathResult> results;
  for (const auto& spec : plan_paths(scene)) results.push_back(run_path(solver, spec, scene.sweep.fuse_tolerance));
  ASSERT_EQ(results.size(), 6u);
  std::vector<double> E(6);
  for (std::size_t i = 0; i < results.size(); ++i) {
    const auto& r = results[i];
    EXPECT_FALSE(r.fuse.has_value());
    // Positive homogeneity: every step has the same modulus (QP tolerance 1e-9).
    E[i] = modulus(r.spec, r.steps.front());
    for (const auto& step : r.steps) {
      EXPECT_TRUE(step.converged);
      EXPECT_NEAR(modulus(r.spec, step) / E[i], 1.0, 1e-7);
    }
    // The warm start (λ and SMALBE's multiplier scaled to the new load) is the exact answer of
    // a positively homogeneous step: a check of the gradient, not a new solve (measured 2).
    // The first step is a cold QP (measured 6–100 applications; the norm estimate of ‖PFP‖ is
    // part of building the cached problem, counted in no step), every later one costs less.
    for (std::size_t k = 1; k < r.steps.size(); ++k) {
      EXPECT_LE(r.steps[k].operator_applications, 10) << "step " << k << " of path " << i;
      EXPECT_LT(r.steps[k].operator_applications, r.steps[0].operator_applications) << "step " << k << " of path " << i;
    }
  }
  // Stiff fibres: softer in tension than in compression, in every direction.
  for (int d = 0; d < 3; ++d) EXPECT_LT(E[2 * d] * 1.2, E[2 * d + 1]) << "direction " << d;
  // 0° and 90° on a centred square cell: the mesh is symmetric under the 90° rotation up to
  // the shorter-diagonal choice in exactly square quads, so equal to discretisation level.
  EXPECT_NEAR(E[0] / E[4], 1.0, 1e-3);
  EXPECT_NEAR(E[1] / E[5], 1.0, 1e-3);
  // 45° differs (square symmetry, not isotropy).
  EXPECT_GT(std::abs(E[2] / E[0] - 1), 0.01);
}

// [sweep] sphere: N directions spread over the unit sphere of (σxx, σyy, √2σxy), loaded along +N;
// one load each without adhesion, every |magnitude| with it; refused on the symmetry boundary.
TEST(Sweep, SphereDirectionsCoverTheStressSphere) {
  Scene s = make_scene(1, 1, 0.3, Boundary::traction, 10, 1, 0, {0}, {-2, 1, -1, 3});
  s.sweep.sphere = 40;
  const auto paths = plan_paths(s);
  ASSERT_EQ(paths.size(), 2u + 40u);
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (std::size_t i = 2; i < paths.size(); ++i) {
    const PathSpec& p = paths[i];
    EXPECT_TRUE(p.sphere);
    EXPECT_EQ(p.sign, 1);
    EXPECT_TRUE(std::isnan(p.direction_deg));
    const Eigen::Vector3d N = p.state.in_plane();
    EXPECT_NEAR(N(0) * N(0) + N(1) * N(1) + 2 * N(2) * N(2), 1.0, 1e-15);  // unit Frobenius norm
    EXPECT_EQ(p.loads, std::vector<double>{3.0});                          // no adhesion: the largest |magnitude| only
    mean += Eigen::Vector3d(N(0), N(1), std::sqrt(2.0) * N(2)) / 40;
  }
  // Evenly spread: the centroid of the points is near the centre (z exactly, x and y to O(1/N)).
  EXPECT_NEAR(mean(2), 0, 1e-15);
  EXPECT_LT(mean.norm(), 0.05);
  s.interface = {0.1, 0.1};
  EXPECT_EQ(plan_paths(s).back().loads, (std::vector<double>{1, 2, 3}));
  s.load.boundary = Boundary::symmetry;
  try {
    validate(s);
    ADD_FAILURE() << "a sphere on the symmetry boundary was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("[sweep] sphere = 40"), std::string::npos) << e.what();
  }
}

// Why one magnitude per sphere direction suffices without adhesion: the response is positively
// homogeneous. Solved at 1e-12 (the QP's relative tolerance), the strain at 3σ̄ is 3 times the
// strain at σ̄ to 1e-9 relative in every direction (round-off of the two solves, amplified by
// the conditioning of F, ~1e2, and the active-set agreement, which is exact here).
TEST(Sweep, WithoutAdhesionTheSphereIsPositivelyHomogeneous) {
  Scene s = make_scene(1, 1, 0.3, Boundary::periodic, 20, 1, 0, {0}, {1});
  s.solver.tolerance = 1e-12;
  const mesh::Mesh m = mesh::build_mesh(s.geometry);
  feti::ContactSolver solver(m, s);
  for (const Eigen::Vector3d& N : sphere_directions(8)) {
    const feti::Solution one = solver.solve(0.01 * N, solver.intact());
    const feti::Solution three = solver.solve(0.03 * N, solver.intact());
    ASSERT_TRUE(one.converged() && three.converged()) << one.qp.message << three.qp.message;
    EXPECT_LE((three.strain - 3 * one.strain).norm(), 1e-9 * three.strain.norm()) << N.transpose();
  }
}

// The thesis' tension fuse (scenes/fuse.toml) on a smaller block: stiff fibres, weak adhesion, tension along x.
TEST_P(SweepOrders, AdhesionBondedBelowOnsetThenAFuse) {
  const Scene scene = make_scene(2, 2, 0.4, Boundary::symmetry, 1e5, 1e3, 10, {0}, {3, 6.5}, GetParam());
  const mesh::Mesh m = mesh::build_mesh(scene.geometry);
  feti::ContactSolver solver(m, scene);
  const auto paths = plan_paths(scene);
  ASSERT_EQ(paths.size(), 1u);
  const double onset = solver.debond_onset(paths[0].state.in_plane());
  const PathResult r = run_path(solver, paths[0], scene.sweep.fuse_tolerance);
  // Bonded modulus from one solve with unbreakable bonds.
  Scene bonded = scene;
  bonded.interface = {1e12, 1e12};
  feti::ContactSolver bonded_solver(m, bonded);
  const double E_bonded = 1 / bonded_solver.solve_fixed({1, 0, 0}, bonded_solver.intact()).strain(0);
  bool saw_first_break = false;
  for (std::size_t i = 0; i < r.steps.size(); ++i) {
    const Step& step = r.steps[i];
    EXPECT_TRUE(step.converged);
    if (step.broken_bonds == 0) {
      EXPECT_NEAR(modulus(r.spec, step) / E_bonded, 1.0, 1e-7) << "load " << step.load;
    } else if (!saw_first_break) {
      saw_first_break = true;
      // The first break happens at the predicted onset, inserted as a step, and the step before
      // it is within the bracket tolerance.
      EXPECT_EQ(step.load, onset);
      ASSERT_GT(i, 0u);
      EXPECT_EQ(r.steps[i - 1].broken_bonds, 0);
      EXPECT_LE(onset - r.steps[i - 1].load, scene.sweep.fuse_tolerance * onset);
    }
  }
  EXPECT_TRUE(saw_first_break);
  ASSERT_TRUE(r.fuse.has_value());
  const Fuse& f = *r.fuse;
  EXPECT_EQ(f.onset_load, onset);
  EXPECT_LE(f.load_after - f.load_before, scene.sweep.fuse_tolerance * f.load_after);
  EXPECT_GE(f.strain_after(0), 1.5 * f.strain_before(0))
      << "before " << f.strain_before(0) << " after " << f.strain_after(0);
  // Loads along the path never decrease (history is monotone).
  for (std::size_t i = 1; i < r.steps.size(); ++i) EXPECT_GE(r.steps[i].load, r.steps[i - 1].load);
}

}  // namespace
}  // namespace dualcell::sweep

namespace dualcell::sweep {
namespace {

// A scene with the cure's temperature change (docs/theory/model.md §1a): every path holds ΔT and
// starts with the cool-down (its first step, at load 0: the strain of the cool-down solved alone,
// bit for bit), its onset is the affine one from the cool-down (feti::ContactSolver::debond_onset,
// exact there: tests/feti/thermal_test.cpp) and inserted as a step, and the path is bonded below
// it: every step's strain minus the cool-down's is the bonded compliance times the load, to the
// solver's 1e-9 amplified (asked 1e-7).
TEST(SweepThermal, EveryPathStartsFromTheCoolDownAndBreaksAtTheAffineOnset) {
  Scene scene = parse_scene(testing::scene_text(1, 1, 2, 0.3), "test.toml");
  scene.fibre = {20.0, 0.25};
  scene.matrix = {3.5, 0.35};
  scene.fibre.expands = scene.matrix.expands = true;
  scene.fibre.alpha = scene.fibre.alpha_L = 6e-6;
  scene.matrix.alpha = scene.matrix.alpha_L = 6e-5;
  scene.load.boundary = Boundary::periodic;
  scene.load.delta_T = -20;
  scene.interface = {0.02, 0.05};
  scene.sweep.directions_deg = {0, 90};
  scene.sweep.magnitudes = {-0.2, -0.05, 0.05, 0.2};
  scene.solver.tolerance = 1e-9;
  validate(scene);
  const mesh::Mesh m = mesh::build_mesh(scene.geometry);
  feti::ContactSolver solver(m, scene);
  const feti::Solution cool =
      solver.solve(MacroState::stress(Eigen::Vector3d::Zero()).hold(MacroState::dT, -20), solver.intact());
  ASSERT_TRUE(cool.converged());
  ASSERT_EQ(cool.newly_broken, 0) << "this cool-down breaks nothing";
  Scene bonded = scene;
  bonded.interface = {1e12, 1e12};
  feti::ContactSolver bonded_solver(m, bonded);
  int fuses = 0;
  for (const PathSpec& spec : plan_paths(scene)) {
    EXPECT_EQ(spec.state.delta_T(), -20);
    EXPECT_TRUE(spec.in_plane()) << "the held ΔT is every path's, not a component along the fibres";
    const PathResult r = run_path(solver, spec, scene.sweep.fuse_tolerance);
    ASSERT_FALSE(r.steps.empty());
    EXPECT_EQ(r.steps[0].load, 0);
    EXPECT_EQ(r.steps[0].strain, cool.strain) << "the cool-down, bit for bit";
    const double onset = spec.sign * solver.debond_onset(spec.sign * spec.state.in_plane());
    ASSERT_TRUE(std::isfinite(onset) && onset != 0);
    const Eigen::Vector3d compliance =
        bonded_solver.solve_fixed(spec.state.in_plane(), bonded_solver.intact()).strain;  // per unit load
    for (const Step& step : r.steps) {
      if (step.broken_bonds > 0) continue;
      const Eigen::Vector3d expected = cool.strain + step.load * compliance;
      EXPECT_LE((step.strain - expected).norm(), 1e-7 * expected.norm()) << "load " << step.load;
    }
    if (r.fuse) {
      ++fuses;
      EXPECT_EQ(r.fuse->onset_load, onset);
    }
  }
  EXPECT_GE(fuses, 1) << "the loads pass the onset on some path";
}

}  // namespace
}  // namespace dualcell::sweep
