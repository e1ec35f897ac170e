// Longitudinal shear of a cell (primal/antiplane.hpp, docs/method.md §3b) against what holds
// for 2D conductivity whatever the geometry: a homogeneous cell's modulus, Keller's theorem in
// Mendelson's tensor form, and fibres that have lost their bonds.
#include "primal/antiplane.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <array>

#include "test_util.hpp"

namespace dualcell::primal {
namespace {

// A periodic cell of fibre radius 0.35, off centre (no symmetry helps), at mesh degree k.
mesh::Mesh cell_mesh(int degree) {
  Scene s = parse_scene(testing::scene_text(1, 1, degree, 0.35), "test.toml");
  s.geometry.fibre_offset = {0.08, -0.05};
  s.load.boundary = Boundary::periodic;
  return mesh::build_mesh(s.geometry);
}

// An isotropic material of shear modulus μ (E = 2μ(1 + ν)).
Material of_shear_modulus(double mu) { return {2 * mu * 1.25, 0.25}; }

// R, the rotation by 90°: Keller–Mendelson, G(μ_a, μ_b) R G(μ_b, μ_a) Rᵀ = μ_a μ_b I.
Eigen::Matrix2d rotation() {
  Eigen::Matrix2d R;
  R << 0, -1, 1, 0;
  return R;
}

// One material everywhere: w̃ = 0 and G = μ I, to round-off.
TEST(LongitudinalShear, AHomogeneousCellHasItsOwnModulus) {
  const mesh::Mesh m = cell_mesh(2);
  const LongitudinalShear s = longitudinal_shear(m, of_shear_modulus(3), of_shear_modulus(3));
  EXPECT_LE((s.G - 3 * Eigen::Matrix2d::Identity()).norm(), 1e-12);
  EXPECT_LE(s.w_tilde.norm(), 1e-12);
}

// Keller's theorem: exchanging the phases' moduli, G(μ_f, μ_m) R G(μ_m, μ_f) Rᵀ = μ_f μ_m I for any
// geometry. It is a property of the continuum: conforming elements overestimate both moduli, so
// the product lies above by the discretisation error, which falls with the mesh (measured
// 6.0e-4, 4.7e-5, 3.3e-6 at degree 2, 4, 8: p2's h⁴ in energy). Asked: above, falling at least
// ten-fold per doubling, below 1e-5 at degree 8.
TEST(LongitudinalShear, ExchangingThePhasesMeetsKellersTheorem) {
  std::array<double, 3> error{};
  const std::array<int, 3> degrees{2, 4, 8};
  for (int k = 0; k < 3; ++k) {
    const mesh::Mesh m = cell_mesh(degrees[k]);
    const Eigen::Matrix2d a = longitudinal_shear(m, of_shear_modulus(20), of_shear_modulus(1)).G;
    const Eigen::Matrix2d b = longitudinal_shear(m, of_shear_modulus(1), of_shear_modulus(20)).G;
    const Eigen::Matrix2d product = a * rotation() * b * rotation().transpose() / 20.0;
    EXPECT_GT(product(0, 0), 1) << "degree " << degrees[k];
    EXPECT_GT(product(1, 1), 1) << "degree " << degrees[k];
    error[k] = (product - Eigen::Matrix2d::Identity()).norm();
  }
  EXPECT_LT(error[1], error[0] / 10);
  EXPECT_LT(error[2], error[1] / 10);
  EXPECT_LT(error[2], 1e-5);
}

// A fibre whose bonds are all broken carries no longitudinal shear (w jumps freely across the
// rim): the cell is the matrix with holes, whatever the fibre (to round-off), and against rigid
// fibres Keller gives G(holes) R G(rigid) Rᵀ = μ_m² I. Rigid as 10⁶ μ_m, whose own error is of
// that order; the discretisation's as above (measured 7.5e-4, 5.7e-5, 2.4e-6).
TEST(LongitudinalShear, BrokenBondsLeaveTheMatrixWithHoles) {
  std::array<double, 3> error{};
  const std::array<int, 3> degrees{2, 4, 8};
  for (int k = 0; k < 3; ++k) {
    const mesh::Mesh m = cell_mesh(degrees[k]);
    const std::vector<char> broken(m.interface_pairs.size(), 0);
    const Eigen::Matrix2d holes = longitudinal_shear(m, of_shear_modulus(20), of_shear_modulus(1), broken).G;
    const Eigen::Matrix2d soft = longitudinal_shear(m, of_shear_modulus(0.05), of_shear_modulus(1), broken).G;
    EXPECT_LE((holes - soft).norm(), 1e-12) << "degree " << degrees[k];
    EXPECT_LT(holes(0, 0), 1) << "softer than the matrix";
    const Eigen::Matrix2d rigid = longitudinal_shear(m, of_shear_modulus(1e6), of_shear_modulus(1)).G;
    error[k] = (holes * rotation() * rigid * rotation().transpose() - Eigen::Matrix2d::Identity()).norm();
  }
  EXPECT_LT(error[1], error[0] / 10);
  EXPECT_LT(error[2], error[1] / 5);
  EXPECT_LT(error[2], 1e-5);
}

// The condensed form (condense_longitudinal_shear) is the same linear algebra as the one-body
// solve, rearranged: for any bond state, the forces that tie the bonded pairs' jumps,
//   [H_BB G_Bᵀ; G_B 0] (q_B, μ) = (Y_B Γ, 0),
// give ⟨τ⟩ = D0 Γ + Y_Bᵀ q_B/|Ω| equal to longitudinal_shear's G Γ for that state, to round-off
// of the solves (measured 1.6e-15 of G at most; asked 1e-12, the CHOLMOD solves' round-off on a
// K of condition near 10⁴ times a margin); the open cell's D0 is the one with every bond broken.
TEST(LongitudinalShear, TheCondensedPairsGiveEveryBondStatesModulus) {
  const mesh::Mesh m = cell_mesh(3);
  const Material fibre = of_shear_modulus(20), matrix = of_shear_modulus(1);
  const CondensedShear c = condense_longitudinal_shear(m, fibre, matrix);
  const int P = static_cast<int>(m.interface_pairs.size());
  ASSERT_EQ(c.H.rows(), P);
  ASSERT_EQ(c.G.rows(), 1) << "one fibre: one floating piece";
  const std::vector<char> none(P, 0);
  EXPECT_LE((c.D0 - longitudinal_shear(m, fibre, matrix, none).G).norm(), 1e-12);
  const double volume = m.block_width() * m.block_height();
  // Every pair, none, the first half of the rim, every third pair.
  std::vector<std::vector<char>> states{std::vector<char>(P, 1), none, none, none};
  for (int p = 0; p < P; ++p) {
    states[2][p] = p < P / 2;
    states[3][p] = p % 3 == 0;
  }
  for (std::size_t s = 0; s < states.size(); ++s) {
    std::vector<int> B;
    for (int p = 0; p < P; ++p)
      if (states[s][p]) B.push_back(p);
    const int b = static_cast<int>(B.size());
    Eigen::MatrixXd K = Eigen::MatrixXd::Zero(b + 1, b + 1), rhs = Eigen::MatrixXd::Zero(b + 1, 2);
    for (int i = 0; i < b; ++i) {
      for (int j = 0; j < b; ++j) K(i, j) = c.H(B[i], B[j]);
      K(i, b) = K(b, i) = c.G(0, B[i]);
      rhs.row(i) = c.Y.row(B[i]);
    }
    Eigen::Matrix2d G = c.D0;
    if (b > 0) {
      const Eigen::MatrixXd q = K.fullPivLu().solve(rhs).topRows(b);
      for (int i = 0; i < b; ++i) G += c.Y.row(B[i]).transpose() * q.row(i) / volume;
    }
    const Eigen::Matrix2d expected = longitudinal_shear(m, fibre, matrix, states[s]).G;
    EXPECT_LE((G - expected).norm(), 1e-12 * expected.norm()) << "state " << s;
  }
  // Bonding stiffens: every state between the open cell and the bonded one.
  EXPECT_GT(longitudinal_shear(m, fibre, matrix).G(0, 0), c.D0(0, 0) * 1.5);
}

}  // namespace
}  // namespace dualcell::primal
