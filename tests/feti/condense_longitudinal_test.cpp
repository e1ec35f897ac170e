// The exact law with the strain along the fibres (a scene's [load] macro = "full", docs/method.md
// §16a): the cell condensed with the ε33 column against the full dual solve of generalised plane
// strain (ContactSolver::solve_fixed with the macro state's ε33) at loads no condensation step saw, with contact
// closing and opening and with bonds; against its own algebra (reciprocity, the tangent as the
// derivative, σ33 as the energy's); and the transverse law unchanged beside it.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>

#include "core/strain.hpp"
#include "feti/condense.hpp"
#include "feti/solver.hpp"
#include "hill_relations.hpp"
#include "primal/antiplane.hpp"
#include "shear_cascade.hpp"
#include "test_util.hpp"

namespace dualcell::feti {
namespace {

// The full solver stops at a relative projected gradient of 1e-10, which reaches the macro strain
// and σ33 amplified by the dual problem's conditioning (≈ 1e2): 1e-7 relative, as the transverse
// law's test (condense_test.cpp). The law's own evaluations are exact to round-off.
constexpr double against_solver = 1e-7;

Scene cell_scene(Boundary boundary, double strength, Macro macro = Macro::full) {
  Scene s = parse_scene(testing::scene_text(1, 1, 2, 0.3, "", "p2"), "test.toml");
  s.fibre = {30.0, 0.22};
  s.matrix = {1.0, 0.35};
  s.geometry.fibre_offset = {0.07, -0.04};  // no symmetry helps
  s.load.boundary = boundary;
  s.load.macro = macro;
  s.interface.normal_strength = s.interface.tangential_strength = strength;
  s.solver.tolerance = 1e-10;
  return s;
}

// The law at (σ̄, ε33) against the full solve: ε̄ and σ33, each relative to the response's size.
void expect_cell(law::CellEvaluator& law, ContactSolver& solver, const Eigen::Vector3d& sigma, double eps33,
                 bool shear) {
  // Bonds held: none reaches its strength.
  const Solution s = solver.solve_fixed(MacroState::stress(sigma).hold(MacroState::zz, eps33), solver.intact());
  ASSERT_TRUE(s.converged()) << s.qp.message;
  law::CellHistory h = law.unloaded();
  const law::CellResponse r = law.at(MacroState::stress(sigma).hold(MacroState::zz, eps33), h);
  ASSERT_TRUE(r.ok) << r.message;
  Eigen::Vector3d expected = engineering_from_tensor(s.strain), strain = r.strain;
  if (!shear) expected(2) = strain(2) = 0;
  const double size = expected.norm() + std::abs(eps33);
  EXPECT_LE((strain - expected).norm(), against_solver * size) << sigma.transpose() << " ε33 " << eps33;
  EXPECT_NEAR(r.stress_zz, s.average_stress_zz, against_solver * (std::abs(s.average_stress_zz) + sigma.norm()))
      << sigma.transpose() << " ε33 " << eps33;
  EXPECT_EQ(r.broken, 0);
}

// Without adhesion, periodic and on the symmetry boundary: stretched along the fibres (rims
// closed), shortened (rims open), combined with in-plane loads of both signs.
TEST(CondensedLongitudinal, ReproducesGeneralisedPlaneStrainWithContact) {
  for (const Boundary boundary : {Boundary::periodic, Boundary::symmetry}) {
    const bool shear = boundary != Boundary::symmetry;
    const Scene scene = cell_scene(boundary, 0.0);
    const mesh::Mesh mesh = mesh::build_mesh(scene.geometry);
    ContactSolver solver(mesh, scene);
    const law::CondensedCell cell = condense(solver.setup());
    ASSERT_EQ(cell.longitudinal, 1);
    EXPECT_EQ(law::consistency_problem(cell), "");
    // Reciprocity (A33 against −∂σ33/∂σ̄, y33 against |Ω| ∂σ33/∂p) to the elimination's round-off
    // (measured 1e-14 … 1e-13; asked 1e-9, as the transverse law's test).
    EXPECT_LE(cell.reciprocity_error, 1e-9);
    // The open cell stretched along the fibres: each phase in uniaxial stress, which leaves the
    // rims free, so ε̄ = −ν_m ε33 (1, 1, 0) and σ33 = ⟨E⟩ ε33 exactly, on any geometry (to the
    // elimination's round-off, 1e-14 measured; asked 1e-10).
    const double vf = testing::fibre_fraction(mesh);
    EXPECT_NEAR(cell.C33(0, 0), vf * scene.fibre.E + (1 - vf) * scene.matrix.E, 1e-10 * scene.fibre.E);
    for (int k = 0; k < 2; ++k) EXPECT_NEAR(cell.A33(k, 0), -scene.matrix.nu, 1e-10);
    if (shear) {
      EXPECT_NEAR(cell.A33(2, 0), 0, 1e-10);
    }
    law::CellEvaluator law(cell);
    std::mt19937 rng(11);
    std::normal_distribution<double> g;
    for (const double eps33 : {0.01, -0.01}) {
      expect_cell(law, solver, Eigen::Vector3d::Zero(), eps33, shear);
      for (int i = 0; i < 4; ++i) {
        const Eigen::Vector3d sigma = 0.02 * Eigen::Vector3d(g(rng), g(rng), shear ? g(rng) : 0.0).normalized();
        expect_cell(law, solver, sigma, eps33, shear);
      }
    }
  }
}

// With bonds that hold (loads below their strength): the bonded cell, linear in (σ̄, ε33).
TEST(CondensedLongitudinal, ReproducesTheBondedCell) {
  const Scene scene = cell_scene(Boundary::periodic, 1.0);
  const mesh::Mesh mesh = mesh::build_mesh(scene.geometry);
  ContactSolver solver(mesh, scene);
  const law::CondensedCell cell = condense(solver.setup());
  ASSERT_TRUE(cell.adhesion());
  law::CellEvaluator law(cell);
  expect_cell(law, solver, Eigen::Vector3d(0.004, -0.002, 0.001), 0.002, true);
  expect_cell(law, solver, Eigen::Vector3d(-0.003, 0.001, -0.002), -0.001, true);
}

// Strain-driven: the stress-driven response's strain gives its σ̄ and σ33 back; the tangent's ε33
// column and dσ33/dε33 are central differences of the law (piecewise linear: exact within a piece,
// the step 1e-7 of the load stays inside one); σ33 is the energy's derivative in ε33.
TEST(CondensedLongitudinal, TheStrainDrivenLawIsItsInverseWithItsTangentAndEnergy) {
  const Scene scene = cell_scene(Boundary::periodic, 0.0);
  const mesh::Mesh mesh = mesh::build_mesh(scene.geometry);
  ContactSolver solver(mesh, scene);
  const law::CondensedCell cell = condense(solver.setup());
  law::CellEvaluator law(cell);
  for (const auto& [sigma, eps33] : {std::pair{Eigen::Vector3d(0.01, -0.004, 0.003), 0.005},
                                     std::pair{Eigen::Vector3d(-0.008, 0.002, -0.001), -0.004}}) {
    law::CellHistory h = law.unloaded();
    const law::CellResponse r = law.at(MacroState::stress(sigma).hold(MacroState::zz, eps33), h);
    ASSERT_TRUE(r.ok) << r.message;
    law::CellHistory h2 = law.unloaded();
    const law::CellResponse back = law.at(MacroState::strain(r.strain).hold(MacroState::zz, eps33), h2);
    ASSERT_TRUE(back.ok) << back.message;
    EXPECT_LE((back.stress - sigma).norm(), 1e-9 * sigma.norm());
    EXPECT_NEAR(back.stress_zz, r.stress_zz, 1e-9 * std::abs(r.stress_zz));

    const double step = 1e-7 * std::abs(eps33);
    law::CellHistory hp = law.unloaded(), hm = law.unloaded();
    const law::CellResponse plus = law.at(MacroState::strain(r.strain).hold(MacroState::zz, eps33 + step), hp);
    const law::CellResponse minus = law.at(MacroState::strain(r.strain).hold(MacroState::zz, eps33 - step), hm);
    const Eigen::Vector3d column = (plus.stress - minus.stress) / (2 * step);
    EXPECT_LE((column - back.tangent_zz).norm(), 1e-6 * back.tangent.norm());
    EXPECT_NEAR((plus.stress_zz - minus.stress_zz) / (2 * step), back.tangent_zz_zz, 1e-6 * back.tangent_zz_zz);
    EXPECT_NEAR((plus.energy - minus.energy) / (2 * step), back.stress_zz, 1e-6 * std::abs(back.stress_zz));
    // The symmetry of the mixed energy: dσ33/dε̄ is the column dσ̄/dε33.
    for (int k = 0; k < 3; ++k) {
      const double dk = 1e-7 * r.strain.norm();
      law::CellHistory a = law.unloaded(), b = law.unloaded();
      const double zz_plus =
          law.at(MacroState::strain(r.strain + dk * Eigen::Vector3d::Unit(k)).hold(MacroState::zz, eps33), a).stress_zz;
      const double zz_minus =
          law.at(MacroState::strain(r.strain - dk * Eigen::Vector3d::Unit(k)).hold(MacroState::zz, eps33), b).stress_zz;
      EXPECT_NEAR((zz_plus - zz_minus) / (2 * dk), back.tangent_zz(k), 1e-6 * back.tangent.norm()) << k;
    }
  }
}

// The transverse law (the default [load] macro) has no ε33 data, refuses an ε33, and its in-plane
// members are the full law's: the extra column leaves them as they were, to the elimination's
// round-off.
TEST(CondensedLongitudinal, TheTransverseLawIsTheFullLawsInPlanePart) {
  const Scene full = cell_scene(Boundary::periodic, 0.0);
  const Scene transverse = cell_scene(Boundary::periodic, 0.0, Macro::transverse);
  const mesh::Mesh mesh = mesh::build_mesh(full.geometry);
  ContactSolver solver_full(mesh, full), solver_transverse(mesh, transverse);
  const law::CondensedCell a = condense(solver_full.setup()), b = condense(solver_transverse.setup());
  EXPECT_EQ(b.longitudinal, 0);
  EXPECT_EQ(b.A33.size() + b.C33.size() + b.y33.size(), 0);
  EXPECT_LE((a.S0 - b.S0).norm(), 1e-12 * b.S0.norm());
  EXPECT_LE((a.Y - b.Y).norm(), 1e-12 * b.Y.norm());
  EXPECT_LE((a.H - b.H).norm(), 1e-12 * b.H.norm());
  law::CellEvaluator law(b);
  law::CellHistory h = law.unloaded();
  const law::CellResponse r = law.at(MacroState::strain(Eigen::Vector3d(0.01, 0, 0)).hold(MacroState::zz, 0.01), h);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.message.find("no strain along the fibres"), std::string::npos) << r.message;
  EXPECT_TRUE(std::isnan(law.at_strain(Eigen::Vector3d(0.01, 0, 0), h).stress_zz));
}

// The shear along the fibres (docs/method.md §16a): the exact law's shear rows against the
// one-body antiplane solve (primal::longitudinal_shear, which knows nothing of the condensation)
// in the bond states the law reaches: bonded, a pattern of broken pairs, and the state a debond
// cascade under Γ alone ends in. The same linear algebra rearranged: 1e-10 of G (measured a few
// 1e-15 in the primal test; here the condensation's dense solves of 64 pairs add their round-off).
// Without adhesion the cell has no shear rows and ⟨τ⟩ = D0z Γ, the fibres as holes.
TEST(CondensedLongitudinal, TheShearAlongTheFibresIsTheAntiplaneSolveOfItsBondState) {
  const Scene scene = cell_scene(Boundary::periodic, 1.0);
  const mesh::Mesh mesh = mesh::build_mesh(scene.geometry);
  ContactSolver solver(mesh, scene);
  const law::CondensedCell cell = condense(solver.setup());
  ASSERT_EQ(cell.shear, 2);
  ASSERT_EQ(cell.shear_rows, cell.n_pairs);
  ASSERT_EQ(law::consistency_problem(cell), "");
  law::CellEvaluator law(cell);
  const auto primal_G = [&](const std::vector<std::uint8_t>& bonded) {
    return primal::longitudinal_shear(mesh, scene.fibre, scene.matrix, std::vector<char>(bonded.begin(), bonded.end()))
        .G;
  };
  const Eigen::Vector2d gamma(0.002, -0.001);  // far below any pair's strength along z
  // Bonded, then every third pair broken: held bonds, no pair at its strength.
  std::vector<std::uint8_t> pattern = cell.bonded;
  for (std::size_t q = 0; q < pattern.size(); q += 3) pattern[q] = 0;
  for (const auto& bonded : {cell.bonded, pattern}) {
    law::CellHistory h = law.unloaded();
    h.bonded = bonded;
    const law::CellResponse r =
        law.at(MacroState::strain(Eigen::Vector3d::Zero()).hold_shear(gamma), h, law::BondMode::held);
    ASSERT_TRUE(r.ok) << r.message;
    const Eigen::Matrix2d G = primal_G(bonded);
    EXPECT_LE((r.shear_z - G * gamma).norm(), 1e-10 * (G * gamma).norm());
    EXPECT_LE((r.tangent_z - G).norm(), 1e-10 * G.norm());
    EXPECT_LT(r.strength_use, 1);
    EXPECT_LE(r.stress.norm(), 1e-12) << "no in-plane stress from Γ alone";
  }
  // Sheared along z until pairs break: the cascade ends in a state whose bonded pairs all hold,
  // so ⟨τ⟩ is that state's antiplane solve; the breaks are irreversible (a smaller Γ afterwards
  // sees the weakened cell).
  law::CellHistory h = law.unloaded();
  law::CellHistory h0 = law.unloaded();
  const double use =
      law.at(MacroState::strain(Eigen::Vector3d::Zero()).hold_shear(gamma), h0, law::BondMode::held).strength_use;
  const Eigen::Vector2d large = 1.5 / use * gamma;  // half as much again as the first pair's strength
  const law::CellResponse r = law.at(MacroState::strain(Eigen::Vector3d::Zero()).hold_shear(large), h);
  ASSERT_TRUE(r.ok) << r.message;
  EXPECT_GT(r.broken, 0);
  EXPECT_LT(r.strength_use, 1);
  const Eigen::Matrix2d G = primal_G(h.bonded);
  EXPECT_LE((r.shear_z - G * large).norm(), 1e-10 * (G * large).norm());
  const law::CellResponse after =
      law.at(MacroState::strain(Eigen::Vector3d::Zero()).hold_shear(gamma), h, law::BondMode::held);
  EXPECT_LE((after.tangent_z - G).norm(), 1e-10 * G.norm());
  EXPECT_LT(after.tangent_z(0, 0), primal_G(cell.bonded)(0, 0));
  // ⟨τ⟩ is the energy's derivative in Γ (held bonds: smooth within the state).
  for (int k = 0; k < 2; ++k) {
    const double step = 1e-6;
    law::CellHistory a = h, b = h;
    const double plus =
        law.at(MacroState::strain(Eigen::Vector3d::Zero()).hold_shear(gamma + step * Eigen::Vector2d::Unit(k)), a,
               law::BondMode::held)
            .energy;
    const double minus =
        law.at(MacroState::strain(Eigen::Vector3d::Zero()).hold_shear(gamma - step * Eigen::Vector2d::Unit(k)), b,
               law::BondMode::held)
            .energy;
    EXPECT_NEAR((plus - minus) / (2 * step), after.shear_z(k), 1e-7 * after.shear_z.norm()) << k;
  }

  const Scene contact = cell_scene(Boundary::periodic, 0.0);
  ContactSolver contact_solver(mesh, contact);
  const law::CondensedCell open = condense(contact_solver.setup());
  EXPECT_EQ(open.shear, 2);
  EXPECT_EQ(open.shear_rows, 0);
  law::CellEvaluator open_law(open);
  law::CellHistory ho = open_law.unloaded();
  const law::CellResponse ro = open_law.at(MacroState::strain(Eigen::Vector3d::Zero()).hold_shear(gamma), ho);
  const Eigen::Matrix2d holes = primal_G(std::vector<std::uint8_t>(open.n_pairs, 0));
  EXPECT_LE((ro.shear_z - holes * gamma).norm(), 1e-12 * (holes * gamma).norm());
}

// The debond cascade along z against the one-body solve's (feti/shear_cascade.hpp): the same
// pairs break at every step of a growing Γ, with the same forces and ⟨τ⟩ to 1e-9.
TEST(CondensedLongitudinal, TheCascadeAlongTheFibresIsTheOneBodySolvesCascade) {
  const Scene scene = cell_scene(Boundary::periodic, 0.5);
  const mesh::Mesh mesh = mesh::build_mesh(scene.geometry);
  ContactSolver solver(mesh, scene);
  const law::CondensedCell cell = condense(solver.setup());
  const int broken = testing::expect_the_one_body_cascade(mesh, scene, cell, Eigen::Vector2d(1.0, 0.3), 1e-9);
  EXPECT_GT(broken, 0);
  EXPECT_LT(broken, cell.n_pairs) << "a partial cascade: some pairs hold";
}

}  // namespace
}  // namespace dualcell::feti
