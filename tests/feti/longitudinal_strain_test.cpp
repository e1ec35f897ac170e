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

// The fibres' share of the block's area, from the elements themselves.
double fibre_fraction(const mesh::Mesh& m) {
  const fem::ElementStresses e = fem::element_stresses(m, {1, 0.3}, {1, 0.3}, Eigen::VectorXd::Zero(m.dim_u()));
  double fibre = 0;
  for (int t = 0; t < e.area.size(); ++t)
    if (m.subdomains[m.triangle_subdomain[t]].is_fibre) fibre += e.area(t);
  return fibre / e.area.sum();
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
    solver.set_longitudinal_strain(0.02);
    const Solution s = solver.solve_fixed(sigma, solver.intact());
    ASSERT_TRUE(s.converged()) << to_string(boundary) << ": " << s.qp.message;
    EXPECT_EQ(s.eps33, 0.02);
    const Eigen::VectorXd f = solver.setup().load(sigma, 0.02);
    EXPECT_GT((f - solver.setup().load(sigma)).norm(), 1e-3 * f.norm()) << "the eigen-stress loads the block";
    const Eigen::VectorXd u_ref = primal::solve_one_body(m, scene, f);
    EXPECT_LE((s.u - u_ref).norm(), 1e-8 * u_ref.norm()) << to_string(boundary);
    const int n = boundary == Boundary::symmetry ? 2 : 3;
    EXPECT_LE((s.average_stress - sigma).head(n).norm(), 1e-7 * sigma.norm()) << to_string(boundary);
    // Without ε33 the longitudinal stress is ν's share of the in-plane one, phase by phase.
    EXPECT_EQ(plane.eps33, 0);
    EXPECT_NE(plane.average_stress_zz, s.average_stress_zz);
    solver.set_longitudinal_strain(0);
    const Solution again = solver.solve_fixed(sigma, solver.intact());
    EXPECT_EQ(again.u, plane.u) << "plane strain, bit for bit";
  }
}

// Hill's exact relations (docs/method.md §3a): for two isotropic phases bonded in any geometry,
// E1 and ν12 follow from the transverse (plane-strain) bulk modulus k23 of the same cell:
//   E1  = ⟨E⟩ + 4 (ν_f − ν_m)² / (1/k_f − 1/k_m)² · (⟨1/k⟩ − 1/k23),
//   ν12 = ⟨ν⟩ + (ν_f − ν_m) / (1/k_m − 1/k_f) · (⟨1/k⟩ − 1/k23),
// k = λ + μ of each phase, ⟨·⟩ the volume average. 1/k23 = ε̄xx + ε̄yy under σ̄ = (1, 1, 0),
// ε33 = 0; E1 = ⟨σ33⟩ and ν12 = −(ε̄xx + ε̄yy)/2 under ε33 = 1, σ̄ = 0. The proof is a state of
// uniform strain (e, e, 0) in every element under ε33 = 1 and σ̄ = (s, s, 0), with
// e = −(λ_f − λ_m)/(2(k_f − k_m)) and s = 2 k_f e + λ_f: both phases then carry the same in-plane
// stress, so it solves the discrete problem exactly, whatever the mesh. Tolerance 1e-7: the QP's
// 1e-10 amplified by cond(PFP) and by the relations' differences of like terms.
TEST(GeneralisedPlaneStrain, HillsRelationsHoldOnAnyGeometry) {
  for (const Eigen::Vector2d& offset : {Eigen::Vector2d(0, 0), Eigen::Vector2d(0.12, -0.07)}) {
    const Scene scene = bonded_scene(Boundary::periodic, offset);
    const mesh::Mesh m = mesh::build_mesh(scene.geometry);
    ContactSolver solver(m, scene);
    const double vf = fibre_fraction(m), vm = 1 - vf;
    const fem::Lame f = fem::lame(scene.fibre), mx = fem::lame(scene.matrix);
    const double kf = f.lambda + f.mu, km = mx.lambda + mx.mu;

    // The uniform state.
    const double e = -(f.lambda - mx.lambda) / (2 * (kf - km)), s = 2 * kf * e + f.lambda;
    solver.set_longitudinal_strain(1);
    const Solution uniform = solver.solve_fixed(Eigen::Vector3d(s, s, 0), solver.intact());
    ASSERT_TRUE(uniform.converged()) << uniform.qp.message;
    EXPECT_LE((uniform.strain - Eigen::Vector3d(e, e, 0)).norm(), 1e-7 * std::abs(e));
    const double zz = vf * (2 * f.lambda * e + f.lambda + 2 * f.mu) + vm * (2 * mx.lambda * e + mx.lambda + 2 * mx.mu);
    EXPECT_NEAR(uniform.average_stress_zz, zz, 1e-7 * zz);

    // k23, then E1 and ν12, against Hill's relations.
    solver.set_longitudinal_strain(0);
    const Solution biaxial = solver.solve_fixed(Eigen::Vector3d(1, 1, 0), solver.intact());
    solver.set_longitudinal_strain(1);
    const Solution axial = solver.solve_fixed(Eigen::Vector3d::Zero(), solver.intact());
    ASSERT_TRUE(biaxial.converged() && axial.converged());
    const double inv_k23 = biaxial.strain(0) + biaxial.strain(1);
    const double E1 = axial.average_stress_zz, nu12 = -(axial.strain(0) + axial.strain(1)) / 2;
    const double Ef = scene.fibre.E, Em = scene.matrix.E, nuf = scene.fibre.nu, num = scene.matrix.nu;
    const double excess = vf / kf + vm / km - inv_k23;  // ⟨1/k⟩ − 1/k23 ≥ 0 (Reuss)
    EXPECT_GT(excess, 0);
    const double E1_hill =
        vf * Ef + vm * Em + 4 * (nuf - num) * (nuf - num) / ((1 / kf - 1 / km) * (1 / kf - 1 / km)) * excess;
    const double nu12_hill = vf * nuf + vm * num + (nuf - num) / (1 / km - 1 / kf) * excess;
    EXPECT_NEAR(E1, E1_hill, 1e-7 * E1_hill) << "offset " << offset.transpose();
    EXPECT_NEAR(nu12, nu12_hill, 1e-7 * nu12_hill) << "offset " << offset.transpose();
  }
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
    solver.set_longitudinal_strain(eps33);
    const Solution s = solver.solve(Eigen::Vector3d::Zero(), solver.intact());
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
  const double vf = fibre_fraction(m);
  const double mixture = vf * contact.fibre.E + (1 - vf) * contact.matrix.E;
  EXPECT_NEAR(E1_shortened, mixture, 1e-8 * mixture);
  EXPECT_NEAR(nu12_shortened, contact.matrix.nu, 1e-8);
  EXPECT_GT(E1, mixture * (1 + 1e-4)) << "bonded, Hill's correction stiffens";
}

// The onset needs a load linear in its factor: with ε33 it is refused, not computed wrong.
TEST(GeneralisedPlaneStrain, TheOnsetRefusesALongitudinalStrain) {
  Scene scene = bonded_scene(Boundary::periodic);
  scene.interface.normal_strength = scene.interface.tangential_strength = 0.05;
  const mesh::Mesh m = mesh::build_mesh(scene.geometry);
  ContactSolver solver(m, scene);
  solver.set_longitudinal_strain(0.01);
  EXPECT_THROW(solver.debond_onset(Eigen::Vector3d(1, 0, 0)), std::logic_error);
  EXPECT_THROW(solver.onset_surface(), std::logic_error);
}

}  // namespace
}  // namespace dualcell::feti
