// A structure of homogeneous cells with the exact law (law/condensed.hpp) against the law's own
// stress-driven evaluation, which solves a different QP: under a uniform stress every point of
// the structure must carry the strain the cell gives that stress, in tension and compression,
// at the first break and past it. And the strain energy the structure minimises is the one whose
// gradient is the stress.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <memory>

#include "feti/condense.hpp"
#include "feti/solver.hpp"
#include "mesh/mesh.hpp"
#include "rve/mesher.hpp"
#include "structure/structure.hpp"
#include "test_util.hpp"

namespace dualcell::structure {
namespace {

// The structure's Newton stops at ‖r‖ ≤ 1e-10 of the forces; its strains carry that times the
// conditioning of the homogenised stiffness (≈ 1e2 for a stiff fibre in a soft matrix): 1e-7
// relative leaves an order of margin. The law's evaluations are exact to round-off.
constexpr double against_newton = 1e-7;

// A periodic p1 cell (degree 2: 16 interface pairs), a stiff fibre in a soft matrix, bonded
// with `strength` (0: contact only).
std::shared_ptr<const law::CondensedCell> cell_law(double strength) {
  Scene s = parse_scene(testing::scene_text(1, 1, 2, 0.3), "test.toml");
  s.geometry.element = Element::p1;
  s.fibre = {30.0, 0.22};
  s.matrix = {1.0, 0.35};
  s.load.boundary = Boundary::periodic;
  s.interface.normal_strength = strength;
  s.interface.tangential_strength = strength;
  const mesh::Mesh mesh = mesh::build_mesh(s.geometry);
  feti::ContactSolver solver(mesh, s);
  return std::make_shared<const law::CondensedCell>(feti::condense(solver.setup()));
}

// A bar of 3 × 1 cells under a uniform traction t_x at its right end: the left end a roller,
// the corner (0, 0) held in y. Its stress is uniform, σ̄ = (t_x, 0, 0), and so is its strain.
StructureScene bar(double traction, StructureScene::BondUnit unit = StructureScene::BondUnit::cell) {
  StructureScene s;
  s.bond_unit = unit;
  s.nx = 3, s.ny = 1, s.elements_per_cell = 1, s.element = Element::p2;
  s.cell_size = 1;
  s.edges[0].kind = EdgeKind::roller;
  s.edges[1].kind = EdgeKind::traction;
  s.edges[1].traction_start = s.edges[1].traction_end = {traction, 0};
  s.supports = {{{0, 0}, false, true, ""}};
  s.watch = {3, 1};
  return s;
}

// The uniform strain the bar's watch node (3, 1) shows: ε_xx = u_x/3, ε_yy = u_y/1.
Eigen::Vector2d bar_strain(const StepResult& r) { return {r.watch_displacement(0) / 3, r.watch_displacement(1)}; }

TEST(ExactLawStructure, UniformStressGivesTheCellsStrainInTensionAndCompression) {
  CellLaw law;
  law.cell = cell_law(0);
  law::CellEvaluator cell(*law.cell);
  double modulus[2];
  for (const double t : {1e-2, -1e-2}) {
    HomogenisedStructure structure(bar(t), law);
    EXPECT_TRUE(std::isinf(structure.first_fuse_factor()));
    const StepResult r = structure.solve_step(1.0);
    ASSERT_TRUE(r.converged);
    EXPECT_EQ(r.newly_broken_units, 0);
    law::CellHistory h = cell.unloaded();
    const law::CellResponse expected = cell.at_stress({t, 0, 0}, h);
    ASSERT_TRUE(expected.ok) << expected.message;
    const Eigen::Vector2d strain = bar_strain(r);
    EXPECT_LE((strain - expected.strain.head<2>()).norm(), against_newton * expected.strain.norm()) << t;
    for (Eigen::Index k = 0; k < r.stress.rows(); ++k)
      EXPECT_LE((r.stress.row(k).transpose() - Eigen::Vector3d(t, 0, 0)).norm(), against_newton * std::abs(t));
    modulus[t > 0] = t / strain(0);
  }
  // The contact cell is bimodular: its gaps open in tension.
  EXPECT_GT(modulus[0], 1.2 * modulus[1]);
}

// The same with the law of a random-fibre RVE's kind (gmsh mesh, METIS parts, a fibre cut by the
// left and right sides): a structure takes any cell's exact law.
TEST(ExactLawStructure, AnRvesLawGivesItsStrainUnderUniformStress) {
  Scene s = parse_scene(testing::scene_text(1, 1, 2, 0.3), "test.toml");
  s.geometry.layout = FibreLayout::list;
  s.geometry.size = {1.0, 1.0};
  s.geometry.fibres = {{{0.0, 0.5}, 0.2}, {{0.55, 0.45}, 0.22}};
  s.fibre = {30.0, 0.22};
  s.matrix = {1.0, 0.35};
  s.load.boundary = Boundary::periodic;
  s.solver.subdomain_dofs = 300;
  const mesh::Mesh mesh = rve::build_rve_mesh(s.geometry, s.solver.subdomain_dofs, "test");
  feti::ContactSolver solver(mesh, s);
  CellLaw law;
  law.cell = std::make_shared<const law::CondensedCell>(feti::condense(solver.setup()));
  law::CellEvaluator cell(*law.cell);
  for (const double t : {1e-2, -1e-2}) {
    HomogenisedStructure structure(bar(t), law);
    const StepResult r = structure.solve_step(1.0);
    ASSERT_TRUE(r.converged);
    law::CellHistory h = cell.unloaded();
    const law::CellResponse expected = cell.at_stress({t, 0, 0}, h);
    ASSERT_TRUE(expected.ok) << expected.message;
    // The RVE is not symmetric: σxx shears it, u_y = ε_yy y + γ x, so the watch node's u_y is not
    // ε_yy alone; ε_xx is, and the stress is uniform everywhere.
    EXPECT_LE(std::abs(bar_strain(r)(0) - expected.strain(0)), against_newton * expected.strain.norm()) << t;
    EXPECT_GT(std::abs(expected.strain(2)), 1e-3 * expected.strain.norm()) << "this RVE shears under sxx";
    for (Eigen::Index k = 0; k < r.stress.rows(); ++k)
      EXPECT_LE((r.stress.row(k).transpose() - Eigen::Vector3d(t, 0, 0)).norm(), against_newton * std::abs(t));
  }
}

// Both bond units (a cell's mean strain is its points' strain here: the field is uniform).
TEST(ExactLawStructure, FirstBreakAndPastItAsTheCellUnderTheSameStress) {
  CellLaw law;
  law.cell = cell_law(0.01);
  ASSERT_TRUE(law.cell->adhesion());
  law::CellEvaluator cell(*law.cell);
  const double t = 1e-2;
  for (const auto unit : {StructureScene::BondUnit::cell, StructureScene::BondUnit::point}) {
    SCOPED_TRACE(unit == StructureScene::BondUnit::cell ? "bonds per cell" : "bonds per point");
    HomogenisedStructure structure(bar(t, unit), law);
    EXPECT_EQ(structure.n_units(), unit == StructureScene::BondUnit::cell ? 3 : 3 * 2 * 6);
    // Every point carries σ̄ = factor·(t, 0, 0): the first bond breaks at the cell's onset.
    const double onset = cell.onset({t, 0, 0});
    ASSERT_TRUE(std::isfinite(onset));
    EXPECT_NEAR(structure.first_fuse_factor(), onset, against_newton * onset);

    const StepResult below = structure.solve_step(0.8 * onset);
    ASSERT_TRUE(below.converged);
    EXPECT_EQ(below.newly_broken_units, 0);
    law::CellHistory h = cell.unloaded();
    law::CellResponse expected = cell.at_stress({0.8 * onset * t, 0, 0}, h);
    EXPECT_LE((bar_strain(below) - expected.strain.head<2>()).norm(), against_newton * expected.strain.norm());

    // Past the first break every unit breaks; the bar ends where the stress-driven cell's
    // cascade ends (no bonded row at its strength, equilibrium at σ̄), with the same broken bonds.
    const StepResult past = structure.solve_step(1.3 * onset);
    ASSERT_TRUE(past.converged);
    EXPECT_EQ(past.newly_broken_units, structure.n_units());
    expected = cell.at_stress({1.3 * onset * t, 0, 0}, h);
    ASSERT_TRUE(expected.ok) << expected.message;
    ASSERT_GT(expected.broken, 0);
    EXPECT_LE((bar_strain(past) - expected.strain.head<2>()).norm(), against_newton * expected.strain.norm());
    for (float b : past.broken) EXPECT_FLOAT_EQ(b, static_cast<float>(expected.broken) / law.cell->n_pairs);

    // Unloaded to below the onset the broken bonds stay broken: softer than the intact bar.
    const StepResult back = structure.solve_step(0.8 * onset);
    ASSERT_TRUE(back.converged);
    EXPECT_EQ(back.newly_broken_units, 0);
    EXPECT_EQ(structure.broken_units(), structure.n_units());
    EXPECT_GT(bar_strain(back)(0), 1.05 * bar_strain(below)(0));
    expected = cell.at_stress({0.8 * onset * t, 0, 0}, h);
    EXPECT_LE((bar_strain(back) - expected.strain.head<2>()).norm(), against_newton * expected.strain.norm());
    // t* is measured from the intact state and leaves the structure's state alone.
    EXPECT_NEAR(structure.first_fuse_factor(), onset, against_newton * onset);
    EXPECT_EQ(structure.broken_units(), structure.n_units());
  }
}

// W(ε̄) is the energy the structure minimises: its central difference along random directions
// is σ̄·δ (to the difference's own error, h² times the curvature, and round-off), held bonds
// stay as they were, and the lifted cell is linear in ε̄.
TEST(ExactLawStructure, TheCellsEnergyHasTheStressAsItsGradient) {
  for (const double strength : {0.0, 0.01}) {
    const auto cell = cell_law(strength);
    law::CellEvaluator law(*cell);
    const Eigen::Vector3d strains[] = {{2e-3, -1e-3, 5e-4}, {-1e-3, -2e-3, 1e-3}, {3e-3, 2e-3, 0}};
    for (const Eigen::Vector3d& e : strains) {
      law::CellHistory h = law.unloaded();
      const law::CellResponse r = law.at_strain(e, h, law::BondMode::held);
      ASSERT_TRUE(r.ok) << r.message;
      EXPECT_EQ(h.bonded, cell->bonded);
      const Eigen::Vector3d delta = Eigen::Vector3d(0.3, -0.5, 0.8).normalized();
      const double step = 1e-6 * e.norm();
      law::CellHistory hp = law.unloaded(), hm = law.unloaded();
      const double Wp = law.at_strain(e + step * delta, hp, law::BondMode::held).energy;
      const double Wm = law.at_strain(e - step * delta, hm, law::BondMode::held).energy;
      EXPECT_NEAR((Wp - Wm) / (2 * step), r.stress.dot(delta), 1e-6 * r.stress.norm()) << e.transpose();
      EXPECT_GT(r.energy, 0);
      law::CellHistory lifted = law.unloaded();
      const law::CellResponse one = law.at_strain(e, lifted, law::BondMode::lifted);
      const law::CellResponse two = law.at_strain(2 * e, lifted, law::BondMode::lifted);
      EXPECT_LE((two.stress - 2 * one.stress).norm(), 1e-10 * two.stress.norm());
      EXPECT_NEAR(two.strength_use, 2 * one.strength_use, 1e-10 * two.strength_use + 1e-300);
    }
  }
}

}  // namespace
}  // namespace dualcell::structure
