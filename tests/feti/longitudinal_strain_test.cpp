// Generalised plane strain (docs/method.md §3a): a uniform longitudinal strain ε33 beside the
// in-plane load. The dual solver against the one-body primal solve of the same load, and Hill's
// exact relations for two isotropic phases perfectly bonded, which hold for any geometry and on
// the discrete problem itself (a state of uniform strain in each phase solves it exactly).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <tuple>

#include "fem/assembly.hpp"
#include "fem/element.hpp"
#include "feti/solver.hpp"
#include "hill_relations.hpp"
#include "primal/one_body.hpp"
#include "test_util.hpp"

namespace dualcell::feti {
namespace {

// A bonded cell (strengths so large that nothing breaks), glass-like fibre in an epoxy-like
// matrix, p2, moved off centre by `offset`.
Scene bonded_scene(Boundary boundary, const Eigen::Vector2d& offset = Eigen::Vector2d::Zero(), int cells = 1) {
  Scene s = parse_scene(testing::scene_text(cells, cells, 2, 0.3), "test.toml");
  s.fibre = {20.0, 0.2};
  s.matrix = {1.0, 0.35};
  s.geometry.fibre_offset = {offset.x(), offset.y()};
  s.load.boundary = boundary;
  s.interface.normal_strength = s.interface.tangential_strength = 1e12;
  s.solver.tolerance = 1e-10;
  return s;
}

// With ε33 the load gains each subdomain's eigen-stress; the dual solution is still the one-body
// solve of that load (tolerance 1e-8 as BondedEqualsMonolithicPrimalForEveryBoundary: the QP's
// 1e-10 amplified by cond(PFP) ≲ 1e2), the average in-plane stress is still σ̄ (Hill–Mandel,
// normal components only on the symmetry boundary), and plane strain (ε33 = 0) is unchanged.
TEST(GeneralisedPlaneStrain, TheDualSolveIsTheOneBodySolveOfTheLoadWithItsEigenStress) {
  for (Boundary boundary : {Boundary::symmetry, Boundary::traction, Boundary::periodic}) {
    const Scene scene = bonded_scene(boundary, Eigen::Vector2d::Zero(), 2);
    const mesh::Mesh m = mesh::build_mesh(scene.geometry);
    ContactSolver solver(m, scene);
    const Eigen::Vector3d sigma =
        boundary == Boundary::symmetry ? Eigen::Vector3d(0.3, -0.1, 0) : Eigen::Vector3d(0.3, -0.1, 0.2);
    const Solution plane = solver.solve_fixed(sigma, solver.intact());
    const Solution s = solver.solve_fixed(MacroState::stress(sigma).hold(MacroState::zz, 0.02), solver.intact());
    ASSERT_TRUE(s.converged()) << to_string(boundary) << ": " << s.qp.message;
    EXPECT_EQ(s.eps33, 0.02);
    const Eigen::VectorXd f = solver.setup().load(sigma, {0.02});
    EXPECT_GT((f - solver.setup().load(sigma)).norm(), 1e-3 * f.norm()) << "the eigen-stress loads the block";
    const Eigen::VectorXd u_ref = primal::solve_one_body(m, scene, f);
    EXPECT_LE((s.u - u_ref).norm(), 1e-8 * u_ref.norm()) << to_string(boundary);
    const int n = boundary == Boundary::symmetry ? 2 : 3;
    EXPECT_LE((s.average_stress - sigma).head(n).norm(), 1e-7 * sigma.norm()) << to_string(boundary);
    // Without ε33 the longitudinal stress is ν's share of the in-plane one, phase by phase.
    EXPECT_EQ(plane.eps33, 0);
    EXPECT_NE(plane.average_stress_zz, s.average_stress_zz);
    const Solution again = solver.solve_fixed(MacroState::stress(sigma).hold(MacroState::zz, 0), solver.intact());
    EXPECT_EQ(again.u, plane.u) << "plane strain, bit for bit";
  }
}

// Hill's exact relations (hill_relations.hpp) on a centred and an off-centre cell. Tolerance
// 1e-8, issue 55's target: the QP's 1e-10 amplified by cond(PFP) and by the relations' differences
// of like terms (measured at most 4.2e-10 over every cell of these tests, the uniform state's
// strain; E1 and ν12 within 3e-11).
TEST(GeneralisedPlaneStrain, HillsRelationsHoldOnAnyGeometry) {
  for (const Eigen::Vector2d& offset : {Eigen::Vector2d(0, 0), Eigen::Vector2d(0.12, -0.07)}) {
    const Scene scene = bonded_scene(Boundary::periodic, offset);
    const mesh::Mesh m = mesh::build_mesh(scene.geometry);
    testing::expect_hill_relations(m, scene, 1e-8,
                                   "offset (" + std::to_string(offset.x()) + ", " + std::to_string(offset.y()) + ")");
  }
}

// The same with a transversely isotropic fibre (carbon-like ratios: E_L/E_T = 15, ν_LT = 0.2,
// ν_TT = 0.4, G_LT = E_T/2): the relations hold with E_L, ν_LT and the phases' plane-strain bulk
// moduli, to the same 1e-8; and E1 is the axial rule of mixtures ⟨E_L⟩ within 1 % (Hill's
// correction is 5e-4 of it here), more than five times what the transverse E alone would give
// (the carbon ply's thirteen-fold error of an isotropic fibre).
TEST(GeneralisedPlaneStrain, HillsRelationsHoldWithATransverselyIsotropicFibre) {
  Scene scene = bonded_scene(Boundary::periodic, Eigen::Vector2d(0.05, 0.02));
  scene.fibre.axial = true;
  scene.fibre.E_L = 15 * scene.fibre.E;
  scene.fibre.nu = 0.4;
  scene.fibre.nu_LT = 0.2;
  scene.fibre.G_LT = 0.5 * scene.fibre.E;
  validate(scene);
  const mesh::Mesh m = mesh::build_mesh(scene.geometry);
  testing::expect_hill_relations(m, scene, 1e-8, "transversely isotropic fibre");
  feti::ContactSolver solver(m, scene);
  const Solution axial =
      solver.solve_fixed(MacroState::stress(Eigen::Vector3d::Zero()).hold(MacroState::zz, 1), solver.intact());
  const double vf = testing::fibre_fraction(m);
  const double rule = vf * scene.fibre.E_L + (1 - vf) * scene.matrix.E;
  EXPECT_NEAR(axial.average_stress_zz, rule, 0.01 * rule);
  EXPECT_GT(axial.average_stress_zz, 5 * (vf * scene.fibre.E + (1 - vf) * scene.matrix.E));
}

// Without bonds (frictionless contact) ε33 meets the interface's one-sidedness. Stretched along
// the fibres (ε33 > 0) the matrix, of the larger ν, contracts onto the fibre: the rim stays
// closed, and E1 and ν12 are the bonded cell's but for the rim's free sliding (measured: E1 by
// 4e-6, ν12 by 3e-5; asked 1e-4 and 1e-3). Shortened (ε33 < 0) the matrix swells away from the
// fibre: the whole rim opens, the fibre no longer pulls the matrix in, and the phases work apart,
// each a uniform uniaxial state: E1 is the rule of mixtures ⟨E⟩ exactly (Hill's correction gone)
// and ν12 the matrix's own ν (to the solver's 1e-10 amplified by the contrast: asked 1e-8).
TEST(GeneralisedPlaneStrain, WithoutBondsTheFibreStopsPullingTheMatrixInWhenShortened) {
  Scene bonded = bonded_scene(Boundary::periodic);
  Scene contact = bonded;
  contact.interface.normal_strength = contact.interface.tangential_strength = 0;
  const mesh::Mesh m = mesh::build_mesh(bonded.geometry);
  ContactSolver with_bonds(m, bonded), without(m, contact);
  const auto constants = [](ContactSolver& solver, double eps33) {
    const Solution s =
        solver.solve(MacroState::stress(Eigen::Vector3d::Zero()).hold(MacroState::zz, eps33), solver.intact());
    EXPECT_TRUE(s.converged()) << s.qp.message;
    long open = 0;
    for (double f : s.normal_force) open += f == 0;
    return std::tuple{s.average_stress_zz / eps33, -(s.strain(0) + s.strain(1)) / (2 * eps33), open};
  };
  const auto [E1, nu12, none] = constants(with_bonds, 0.01);
  const auto [E1_stretched, nu12_stretched, open_stretched] = constants(without, 0.01);
  const auto [E1_shortened, nu12_shortened, open_shortened] = constants(without, -0.01);
  EXPECT_EQ(none, 0);
  EXPECT_EQ(open_stretched, 0);
  EXPECT_NEAR(E1_stretched, E1, 1e-4 * E1);
  EXPECT_NEAR(nu12_stretched, nu12, 1e-3);
  EXPECT_EQ(open_shortened, static_cast<long>(m.interface_pairs.size()));
  const double vf = testing::fibre_fraction(m);
  const double mixture = vf * contact.fibre.E + (1 - vf) * contact.matrix.E;
  EXPECT_NEAR(E1_shortened, mixture, 1e-8 * mixture);
  EXPECT_NEAR(nu12_shortened, contact.matrix.nu, 1e-8);
  EXPECT_GT(E1, mixture * (1 + 1e-4)) << "bonded, Hill's correction stiffens";
}

// The solver takes the in-plane stress with ε33, Γ and ΔT held (the onset takes the in-plane
// stress alone, by its type, and the scene's ΔT); a temperature change on phases without
// expansion coefficients (a scene built in code, past validate()'s check of [load] delta_T) is
// refused, not taken as no expansion, and so is a strain-driven in-plane state.
TEST(GeneralisedPlaneStrain, TheSolverRefusesAStateItCannotTake) {
  Scene scene = bonded_scene(Boundary::periodic);
  scene.interface.normal_strength = scene.interface.tangential_strength = 0.05;
  const mesh::Mesh m = mesh::build_mesh(scene.geometry);
  ContactSolver solver(m, scene);
  EXPECT_THROW(solver.solve(MacroState::stress(Eigen::Vector3d(1, 0, 0)).hold(MacroState::dT, -100), solver.intact()),
               std::invalid_argument);
  EXPECT_THROW(solver.solve(MacroState::strain(Eigen::Vector3d(1e-3, 0, 0)), solver.intact()), std::invalid_argument);
}

}  // namespace
}  // namespace dualcell::feti
