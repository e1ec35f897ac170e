// The ply's nine constants from the exact law (law/ply.hpp, docs/method.md §3c) against other
// routes: bonded, the inverse of the law's own 4 × 4 tangent (another algebra: no secant steps)
// and the one-body antiplane solve for G12, G13 (τxz or τyz alone: 1/(G⁻¹)₀₀, 1/(G⁻¹)₁₁); without bonds, shortened
// along the fibres, the phases work apart, so E1 = ⟨E⟩ and ν12 = ν13 = ν_m exactly (§3a), and the longitudinal shear is
// the matrix with holes' in tension and compression alike; after the fuse, softer across the
// fibres and along them, E1 unchanged within the Hill correction.
#include "law/ply.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include "feti/condense.hpp"
#include "feti/solver.hpp"
#include "primal/antiplane.hpp"
#include "test_util.hpp"

namespace dualcell::law {
namespace {

struct Cell {
  Scene scene;
  mesh::Mesh mesh;
  CondensedCell cell;
};

Cell full_cell(double strength) {
  Cell c;
  c.scene = parse_scene(testing::scene_text(1, 1, 2, 0.3, "", "p2"), "test.toml");
  c.scene.fibre = {30.0, 0.22};
  c.scene.matrix = {1.0, 0.35};
  c.scene.geometry.fibre_offset = {0.05, -0.03};
  c.scene.load.boundary = Boundary::periodic;
  c.scene.load.macro = Macro::full;
  c.scene.interface.normal_strength = c.scene.interface.tangential_strength = strength;
  c.mesh = mesh::build_mesh(c.scene.geometry);
  feti::ContactSolver solver(c.mesh, c.scene);
  c.cell = feti::condense(solver.setup());
  return c;
}

// Bonded the law is linear: the secants are the compliance S = D⁻¹ of its tangent in (εxx, εyy,
// γxy, ε33), E1 = 1/S44, ν12 = −S14/S44 (the load along the fibres alone: εxx = S14 σ33), E2 =
// 1/S11 … at σ33 = 0, and G12, G13 the one-body solve's: to the secant steps' 1e-9 of the load
// and the law's round-off (asked 1e-8). Tension and compression agree to the same.
TEST(PlyConstants, BondedTheyAreTheInverseOfTheLawsTangentAndTheAntiplaneSolve) {
  const Cell c = full_cell(1.0);
  const PlyTable t = ply_constants(c.cell);
  ASSERT_EQ(t.note, "");
  ASSERT_EQ(t.rows.size(), 4u);
  CellEvaluator law(c.cell);
  CellHistory h = law.unloaded();
  const CellResponse r =
      law.at(MacroState::strain(Eigen::Vector3d(1e-6, 0, 0)).hold(MacroState::zz, 1e-6), h, BondMode::held);
  Eigen::Matrix4d D;
  D.topLeftCorner<3, 3>() = r.tangent;
  D.block<3, 1>(0, 3) = r.tangent_zz;
  D.block<1, 3>(3, 0) = r.tangent_zz.transpose();
  D(3, 3) = r.tangent_zz_zz;
  const Eigen::Matrix4d S = D.inverse();
  const Eigen::Matrix2d G = primal::longitudinal_shear(c.mesh, c.scene.fibre, c.scene.matrix).G;
  const double expected[9] = {1 / S(3, 3),           1 / S(0, 0),           1 / S(1, 1),
                              -S(0, 3) / S(3, 3),    -S(1, 3) / S(3, 3),    -S(0, 1) / S(0, 0),
                              1 / G.inverse()(0, 0), 1 / G.inverse()(1, 1), 1 / S(2, 2)};
  for (int i = 0; i < 2; ++i) {
    const PlyConstants& row = t.rows[i];
    EXPECT_EQ(row.state, PlyState::bonded);
    EXPECT_EQ(row.broken, 0);
    int k = 0;
    for_each_field(ply_constant_fields, row, [&](const auto& field, double v) {
      EXPECT_NEAR(v, expected[k], 1e-8 * std::abs(expected[k])) << field.name << " sign " << row.sign;
      ++k;
    });
  }
}

TEST(PlyConstants, WithoutBondsTheShortenedPlyWorksApartAndCarriesNoShearAlongTheFibres) {
  const Cell c = full_cell(0.0);
  const PlyTable t = ply_constants(c.cell);
  ASSERT_EQ(t.rows.size(), 2u);
  const double vf = M_PI * 0.3 * 0.3, mean_E = vf * 30.0 + (1 - vf) * 1.0;
  std::vector<char> none(c.mesh.interface_pairs.size(), 0);
  const Eigen::Matrix2d holes = primal::longitudinal_shear(c.mesh, c.scene.fibre, c.scene.matrix, none).G;
  for (const PlyConstants& row : t.rows) {
    EXPECT_EQ(row.state, PlyState::contact);
    EXPECT_NEAR(row.G12, 1 / holes.inverse()(0, 0), 1e-12 * holes(0, 0));
    EXPECT_NEAR(row.G13, 1 / holes.inverse()(1, 1), 1e-12 * holes(1, 1));
  }
  const PlyConstants& shortened = t.rows[1];
  ASSERT_EQ(shortened.sign, -1);
  // ⟨E⟩ of the mesh's areas (the p2 rim is a polygon of arcs: 1e-4 of the circle's).
  EXPECT_NEAR(shortened.E1, mean_E, 1e-3 * mean_E);
  EXPECT_NEAR(shortened.nu12, 0.35, 1e-9);
  EXPECT_NEAR(shortened.nu13, 0.35, 1e-9);
  // Open rims: softer across the fibres in tension than in compression.
  EXPECT_LT(t.rows[0].E2, 0.5 * shortened.E2);
}

TEST(PlyConstants, AfterTheFuseThePlyIsSofterAcrossAndAlongTheFibres) {
  const Cell c = full_cell(0.02);
  const PlyTable t = ply_constants(c.cell);
  ASSERT_EQ(t.note, "");
  ASSERT_EQ(t.rows.size(), 4u);
  EXPECT_GT(t.fuse_stress, 0);
  const PlyConstants &bonded = t.rows[0], &fused = t.rows[2];
  ASSERT_EQ(fused.state, PlyState::after_fuse);
  EXPECT_GT(fused.broken, 0);
  EXPECT_LT(fused.E2, bonded.E2);
  EXPECT_LT(fused.G12, bonded.G12);
  EXPECT_NEAR(fused.E1, bonded.E1, 1e-2 * bonded.E1) << "E1 hardly changes (within the Hill correction)";
}

}  // namespace
}  // namespace dualcell::law
