// A temperature change ΔT from the stress-free state (docs/theory/model.md §1a): each phase's
// thermal stress −ΔT β (1, 1, 0) in the plane and −ΔT β33 along z, an eigen-stress like ε33's.
// Checked against what holds exactly on the discrete problem: a uniform thermal strain that both
// phases share leaves no stress, the dual solve is the one-body solve of the same load, the
// thermal stresses are self-equilibrated (Hill–Mandel), Levin's relation gives the effective
// thermal stress from the effective stiffness for any geometry, and the onset along a path from
// the cool-down is affine and exact.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <string>
#include <tuple>

#include "core/strain.hpp"
#include "fem/assembly.hpp"
#include "fem/element.hpp"
#include "feti/condense.hpp"
#include "feti/solver.hpp"
#include "hill_relations.hpp"
#include "law/condensed.hpp"
#include "law/onset.hpp"
#include "primal/one_body.hpp"
#include "rve/mesher.hpp"
#include "test_util.hpp"

namespace dualcell::feti {
namespace {

// A bonded cell (strengths so large that nothing breaks), p2, off centre by `offset`: a
// transversely isotropic carbon-like fibre (E_L/E_T = 15) in an epoxy-like matrix, each with its
// own expansion (the matrix's ten times the fibre's across it, the fibre's slightly negative
// along it), cooled by 100 K.
Scene thermal_scene(Boundary boundary, const Eigen::Vector2d& offset = Eigen::Vector2d::Zero()) {
  Scene s = parse_scene(testing::scene_text(1, 1, 2, 0.3), "test.toml");
  s.fibre = {20.0, 0.25};
  s.fibre.axial = true;
  s.fibre.E_L = 300;
  s.fibre.nu_LT = 0.2;
  s.fibre.G_LT = 15;
  s.matrix = {3.5, 0.35};
  s.fibre.expands = s.matrix.expands = true;
  s.fibre.alpha = 6e-6;
  s.fibre.alpha_L = -5e-7;
  s.matrix.alpha = s.matrix.alpha_L = 6e-5;
  s.geometry.fibre_offset = {offset.x(), offset.y()};
  s.load.boundary = boundary;
  s.load.delta_T = -100;
  s.interface.normal_strength = s.interface.tangential_strength = 1e12;
  s.solver.tolerance = 1e-10;
  validate(s);
  return s;
}

MacroState cooled(const Eigen::Vector3d& sigma, double delta_T, double eps33 = 0) {
  return MacroState::stress(sigma).hold(MacroState::zz, eps33).hold(MacroState::dT, delta_T);
}

// The largest stress component of any element (centroid and average), and of σzz.
double largest_stress(const mesh::Mesh& m, const Scene& scene, const Solution& s) {
  const fem::ElementStresses e = fem::element_stresses(m, scene.fibre, scene.matrix, s.u, {s.eps33, s.delta_T});
  return std::max(
      {e.centroid.cwiseAbs().maxCoeff(), e.average.cwiseAbs().maxCoeff(), e.zz_average.cwiseAbs().maxCoeff()});
}

// Levin's relation in generalised plane strain's four components (εxx, εyy, γxy, ε33): the
// effective thermal stress per kelvin of two bonded phases of any geometry from the effective
// stiffness C*, β* = ⟨β⟩ + (C* − ⟨C⟩)(C_f − C_m)⁻¹(β_f − β_m), each phase's C and β from
// fem::phase_stiffness; vf the fibres' area fraction. Also ⟨β⟩, what it corrects.
struct Levin {
  Eigen::Vector4d beta, beta_mean;
};
Levin levin_beta(const Eigen::Matrix4d& C_eff, const Scene& scene, double vf) {
  const auto phase = [](const Material& material, Eigen::Matrix4d& C, Eigen::Vector4d& beta) {
    const fem::PhaseStiffness P = fem::phase_stiffness(material);
    C.setZero();
    C.topLeftCorner<3, 3>() = P.D;
    C(0, 3) = C(3, 0) = C(1, 3) = C(3, 1) = P.C13;
    C(3, 3) = P.C33;
    beta << P.beta, P.beta, 0, P.beta33;
  };
  Eigen::Matrix4d C_f, C_m;
  Eigen::Vector4d beta_f, beta_m;
  phase(scene.fibre, C_f, beta_f);
  phase(scene.matrix, C_m, beta_m);
  Levin out;
  out.beta_mean = vf * beta_f + (1 - vf) * beta_m;
  out.beta = out.beta_mean + (C_eff - (vf * C_f + (1 - vf) * C_m)) * (C_f - C_m).fullPivLu().solve(beta_f - beta_m);
  return out;
}

// Both phases with the same expansion (α_T across, α_L along, whatever their stiffness), and a
// homogeneous cell (fibre = matrix, transversely isotropic with α_T ≠ α_L): held at ε33 = α_L ΔT
// and zero macro stress, the strain α_T ΔT (1, 1, 0) is compatible and stress-free, so the solve
// must find it: every element's stress within 1e-8 of one phase's thermal stress β ΔT (the
// solver's 1e-10 amplified by cond(PFP), as the other bonded checks), the macro strain α_T ΔT to
// 1e-8. On every boundary of a cell.
TEST(Thermal, AnExpansionBothPhasesShareLeavesNoStress) {
  for (Boundary boundary : {Boundary::symmetry, Boundary::traction, Boundary::periodic}) {
    for (const bool homogeneous : {false, true}) {
      Scene scene = thermal_scene(boundary);
      if (homogeneous) {
        scene.matrix = scene.fibre;
      } else {
        scene.fibre.alpha = scene.matrix.alpha;
        scene.fibre.alpha_L = scene.matrix.alpha_L;
      }
      const std::string what = std::string(to_string(boundary)) + (homogeneous ? ", homogeneous" : ", equal alpha");
      const mesh::Mesh m = mesh::build_mesh(scene.geometry);
      ContactSolver solver(m, scene);
      const double dT = scene.load.delta_T;
      const Solution s =
          solver.solve_fixed(cooled(Eigen::Vector3d::Zero(), dT, scene.fibre.alpha_L * dT), solver.intact());
      ASSERT_TRUE(s.converged()) << what << ": " << s.qp.message;
      EXPECT_EQ(s.delta_T, dT);
      const double scale = std::abs(fem::phase_stiffness(scene.fibre).beta * dT);
      EXPECT_LE(largest_stress(m, scene, s), 1e-8 * scale) << what;
      const double a = scene.fibre.alpha * dT;
      EXPECT_NEAR(s.strain(0), a, 1e-8 * std::abs(a)) << what;
      EXPECT_NEAR(s.strain(1), a, 1e-8 * std::abs(a)) << what;
      EXPECT_NEAR(s.strain(2), 0, 1e-8 * std::abs(a)) << what;
    }
  }
}

// With different expansions the cool-down leaves self-equilibrated stresses: the dual solve is
// the one-body primal solve of the load with the thermal eigen-stress (1e-8, as
// GeneralisedPlaneStrain's), the average in-plane stress is the applied σ̄ (Hill–Mandel; normal
// components only on the symmetry boundary), and with ΔT = 0 the load is the plane-strain one
// bit for bit.
TEST(Thermal, TheDualSolveIsTheOneBodySolveOfTheCoolDown) {
  for (Boundary boundary : {Boundary::symmetry, Boundary::traction, Boundary::periodic}) {
    const Scene scene = thermal_scene(boundary, Eigen::Vector2d(0.05, -0.03));
    const mesh::Mesh m = mesh::build_mesh(scene.geometry);
    ContactSolver solver(m, scene);
    const Eigen::Vector3d sigma =
        boundary == Boundary::symmetry ? Eigen::Vector3d(0.01, -0.005, 0) : Eigen::Vector3d(0.01, -0.005, 0.004);
    for (const Eigen::Vector3d& load : {Eigen::Vector3d(Eigen::Vector3d::Zero()), sigma}) {
      const Solution s = solver.solve_fixed(cooled(load, scene.load.delta_T), solver.intact());
      ASSERT_TRUE(s.converged()) << to_string(boundary) << ": " << s.qp.message;
      const Eigen::VectorXd f = solver.setup().load(load, {0, scene.load.delta_T});
      const Eigen::VectorXd u_ref = primal::solve_one_body(m, scene, f);
      EXPECT_LE((s.u - u_ref).norm(), 1e-8 * u_ref.norm()) << to_string(boundary);
      const int n = boundary == Boundary::symmetry ? 2 : 3;
      const double thermal = std::abs(fem::phase_stiffness(scene.matrix).beta * scene.load.delta_T);
      EXPECT_LE((s.average_stress - load).head(n).norm(), 1e-7 * thermal) << to_string(boundary);
      // The cool-down stresses the cell: the matrix's hoop stress is of the order of its β ΔT.
      EXPECT_GT(largest_stress(m, scene, s), 0.1 * thermal) << to_string(boundary);
    }
    EXPECT_EQ(solver.setup().load(sigma, {0, 0}), solver.setup().load(sigma)) << "no temperature: the same bits";
  }
}

// Levin's relation (docs/theory/model.md §1a): for two phases perfectly bonded, in any geometry,
// the effective thermal stress per kelvin is β* = ⟨β⟩ + (C* − ⟨C⟩)(C_f − C_m)⁻¹(β_f − β_m), here in
// generalised plane strain's four components (εxx, εyy, γxy, ε33). Exact on the discrete problem:
// the uniform strain that gives both phases the same stress solves it, and Betti's reciprocity
// carries it to the cell. C* and β* from five solves of the dual solver (three unit stresses, ε33
// and ΔT alone); asked 1e-8 relative, issue 55's target, as Hill's relations (the QP's 1e-10
// amplified by cond(PFP) and by the relation's differences of like terms; measured 1.7e-10).
TEST(Thermal, LevinsRelationHoldsOnAnyGeometry) {
  for (const Eigen::Vector2d& offset : {Eigen::Vector2d(0, 0), Eigen::Vector2d(0.11, -0.06)}) {
    const Scene scene = thermal_scene(Boundary::periodic, offset);
    const mesh::Mesh m = mesh::build_mesh(scene.geometry);
    ContactSolver solver(m, scene);
    // The mixed response: ε̄ = A σ̄ + a ε33 + t ΔT (engineering shear), σ33 = b·σ̄ + c ε33 + t33 ΔT.
    Eigen::Matrix3d A;
    Eigen::Vector3d a, b, t;
    double c = 0, t33 = 0;
    const auto engineering = [](const Solution& s) {
      return Eigen::Vector3d(s.strain(0), s.strain(1), 2 * s.strain(2));
    };
    for (int j = 0; j < 3; ++j) {
      const Solution s = solver.solve_fixed(MacroState::stress(Eigen::Vector3d::Unit(j)), solver.intact());
      ASSERT_TRUE(s.converged()) << s.qp.message;
      A.col(j) = engineering(s);
      b(j) = s.average_stress_zz;
    }
    const Solution axial = solver.solve_fixed(cooled(Eigen::Vector3d::Zero(), 0, 1), solver.intact());
    const Solution heated = solver.solve_fixed(cooled(Eigen::Vector3d::Zero(), 1), solver.intact());
    ASSERT_TRUE(axial.converged() && heated.converged());
    a = engineering(axial), c = axial.average_stress_zz;
    t = engineering(heated), t33 = heated.average_stress_zz;
    // The effective law σ = C* ε − β* ΔT, from the mixed one.
    using Matrix4 = Eigen::Matrix4d;
    using Vector4 = Eigen::Vector4d;
    const Eigen::Matrix3d Ainv = A.inverse();
    Matrix4 C_eff;
    C_eff.topLeftCorner<3, 3>() = Ainv;
    C_eff.topRightCorner<3, 1>() = -Ainv * a;
    C_eff.bottomLeftCorner<1, 3>() = b.transpose() * Ainv;
    C_eff(3, 3) = c - b.dot(Ainv * a);
    Vector4 beta_eff;
    beta_eff.head<3>() = Ainv * t;
    beta_eff(3) = b.dot(Ainv * t) - t33;
    const Levin levin = levin_beta(C_eff, scene, testing::fibre_fraction(m));
    EXPECT_LE((beta_eff - levin.beta).norm(), 1e-8 * beta_eff.norm())
        << "offset " << offset.transpose() << "\nsolved " << beta_eff.transpose() << "\nLevin  "
        << levin.beta.transpose();
    // And not the mean: the relation's correction is what is checked.
    EXPECT_GT((beta_eff - levin.beta_mean).norm(), 1e-3 * beta_eff.norm());
  }
}

// The onset along a path from the cool-down (adhesion, weak enough to break): the bonded forces
// are affine in the load factor, p0 + t·p, so s* is exact as without ΔT: a solve just below it
// from the cool-down's bond state breaks nothing, just above it breaks a bond; the onset polytope
// (its facets shifted by the cool-down's forces) predicts the same s* (1e-9, as without ΔT). The
// cool-down moves the onset: the radial pressure of a matrix shrinking onto the fibre holds the
// rim closed longer under transverse tension.
TEST(Thermal, TheOnsetFromTheCoolDownIsAffineAndExact) {
  Scene scene = thermal_scene(Boundary::periodic);
  scene.interface.normal_strength = 0.02;
  scene.interface.tangential_strength = 0.05;
  scene.load.delta_T = -20;
  validate(scene);
  Scene warm = scene;
  warm.load.delta_T = 0;
  const mesh::Mesh m = mesh::build_mesh(scene.geometry);
  ContactSolver solver(m, scene), without(m, warm);
  const Solution cool = solver.solve(cooled(Eigen::Vector3d::Zero(), scene.load.delta_T), solver.intact());
  ASSERT_TRUE(cool.converged()) << cool.qp.message;
  ASSERT_EQ(cool.newly_broken, 0) << "this cool-down breaks nothing";
  const law::OnsetSurface polytope = solver.onset_surface();
  ASSERT_TRUE(polytope.linear) << polytope.message;
  const Eigen::Vector3d tension(1, 0, 0);
  EXPECT_GT(solver.debond_onset(tension), 1.05 * without.debond_onset(tension));
  for (const Eigen::Vector3d& N : {tension, Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(-0.6, 0.8, 0.1)}) {
    const double onset = solver.debond_onset(N);
    ASSERT_TRUE(std::isfinite(onset) && onset > 0) << N.transpose();
    EXPECT_NEAR(law::onset_along(polytope, N) / onset, 1.0, 1e-9) << N.transpose();
    EXPECT_EQ(solver.solve(cooled(0.999 * onset * N, scene.load.delta_T), cool.bonds).newly_broken, 0) << N.transpose();
    EXPECT_GE(solver.solve(cooled(1.001 * onset * N, scene.load.delta_T), cool.bonds).newly_broken, 1) << N.transpose();
  }
}

// The cure's pipeline RVE (pipelines/scenes/cure-t300-bsl914c-rve.toml: six T300 fibres in
// BSL914C, the measured constituents with their expansion, cooled by 100 K): its cool-down's
// bonded solve cannot reach the onset's 1e-13 (it stagnated near 1e-11, and the onset was NaN);
// at the scene's tolerance it gives the onset, which a full solve brackets to 0.1 % on each side.
TEST(Thermal, TheOnsetFromTheCoolDownOfAMeasuredRveIsANumber) {
  std::string file = testing::source_dir();
  file.append("/pipelines/scenes/cure-t300-bsl914c-rve.toml");
  const Scene scene = load_scene(file);
  const mesh::Mesh m = rve::build_rve_mesh(scene.geometry, scene.solver.subdomain_dofs, "test");
  ContactSolver solver(m, scene);
  const Solution cool = solver.solve(cooled(Eigen::Vector3d::Zero(), scene.load.delta_T), solver.intact());
  ASSERT_TRUE(cool.converged()) << cool.qp.message;
  ASSERT_EQ(cool.newly_broken, 0) << "this cool-down breaks nothing";
  const Eigen::Vector3d N(1, 0, 0);
  const double onset = solver.debond_onset(N);
  ASSERT_TRUE(std::isfinite(onset) && onset > 0) << onset << ": " << solver.onset_note();
  EXPECT_TRUE(solver.onset_note().empty());
  EXPECT_EQ(solver.solve(cooled(0.999 * onset * N, scene.load.delta_T), cool.bonds).newly_broken, 0);
  EXPECT_GE(solver.solve(cooled(1.001 * onset * N, scene.load.delta_T), cool.bonds).newly_broken, 1);
}

// A cool-down strong enough to break bonds by itself: the onset along any direction is 0 and the
// polytope says why.
TEST(Thermal, ACoolDownThatBreaksBondsHasNoOnsetAroundZero) {
  Scene scene = thermal_scene(Boundary::periodic);
  scene.interface.normal_strength = 0.02;
  scene.interface.tangential_strength = 1e-5;
  validate(scene);
  const mesh::Mesh m = mesh::build_mesh(scene.geometry);
  ContactSolver solver(m, scene);
  const Solution cool = solver.solve(cooled(Eigen::Vector3d::Zero(), scene.load.delta_T), solver.intact());
  ASSERT_TRUE(cool.converged()) << cool.qp.message;
  EXPECT_GE(cool.newly_broken, 1);
  EXPECT_EQ(solver.debond_onset(Eigen::Vector3d(1, 0, 0)), 0);
  const law::OnsetSurface polytope = solver.onset_surface();
  EXPECT_FALSE(polytope.linear);
  EXPECT_NE(polytope.message.find("the cool-down alone"), std::string::npos) << polytope.message;
}

// The bonded ply's expansion (ContactSolver::bonded_expansion: two full solves with the bonds'
// strengths lifted) against Levin's relation evaluated with the cell's exact law, an independent
// route: C* the exact law's bonded tangent in (εxx, εyy, γxy, ε33), β* = ⟨β⟩ + (C* − ⟨C⟩)(C_f −
// C_m)⁻¹(β_f − β_m) and α* = C*⁻¹ β*. On an RVE of two fibres of different radii, one cut by the
// cell's sides (gmsh mesh), so nothing is symmetric and α23 ≠ 0. Asked 1e-8 relative to |α*|, issue
// 55's target: the full solves' 1e-13 and the condensation's round-off, amplified by the
// relation's differences (measured 1.1e-11).
TEST(Thermal, TheBondedPlysExpansionIsLevinsOfItsExactLaw) {
  Scene s = thermal_scene(Boundary::periodic);
  s.geometry.layout = FibreLayout::list;
  s.geometry.size = {1.0, 1.0};
  s.geometry.fibres = {{{0.0, 0.5}, 0.2}, {{0.55, 0.42}, 0.25}};
  s.load.macro = Macro::full;
  s.load.delta_T = 0;
  s.interface.normal_strength = s.interface.tangential_strength = 0.05;
  s.solver.subdomain_dofs = 300;
  validate(s);
  const mesh::Mesh m = rve::build_rve_mesh(s.geometry, s.solver.subdomain_dofs, "test");
  ContactSolver solver(m, s);
  const law::PlyExpansion alpha = solver.bonded_expansion();
  ASSERT_TRUE(alpha.ok) << alpha.note;
  const law::CondensedCell cell = condense(solver.setup());
  ASSERT_EQ(cell.longitudinal, 1);
  law::CellEvaluator evaluator(cell);
  law::CellHistory h = evaluator.unloaded();
  Eigen::Matrix<double, 6, 1> e;
  e << 1e-6, -4e-7, 3e-7, 2e-7, 0, 0;
  const law::CellResponse r = evaluator.at(MacroState::ply_strain(e), h, law::BondMode::lifted);
  ASSERT_TRUE(r.ok) << r.message;
  const Eigen::Matrix4d C_eff = law::ply_tangent(r).topLeftCorner<4, 4>();
  const Eigen::Vector4d beta_eff = levin_beta(C_eff, s, testing::fibre_fraction(m)).beta;
  const Eigen::Vector4d levin = C_eff.fullPivLu().solve(beta_eff);
  const Eigen::Vector4d solved(alpha.alpha2, alpha.alpha3, alpha.alpha23, alpha.alpha1);
  EXPECT_LE((solved - levin).norm(), 1e-8 * levin.norm())
      << "solved " << solved.transpose() << "\nLevin  " << levin.transpose();
  EXPECT_GT(std::abs(alpha.alpha23), 1e-4 * levin.norm()) << "this RVE shears when heated";
  // Between the phases: across the fibres above the matrix's own (the stiff fibres hold it along
  // z, so it swells more across), along them near the fibres' (they carry the axial stiffness).
  EXPECT_LT(alpha.alpha1, 0.2 * s.matrix.alpha);
  EXPECT_GT(alpha.alpha1, s.fibre.alpha_L);
}

// The exact law with its ΔT column (docs/theory/model.md §1a) against the full solve of the same
// state (solve_fixed: bonds held; the bonds here are far from their strength), on the off-centre
// cell: with the strain along the fibres (macro = "full": ε̄ and σ33) and without it (plane
// strain: ε̄), under ΔT alone and with in-plane stresses and ε33 of both signs. Asked 1e-7
// relative, the solver's 1e-10 amplified by the dual problem's conditioning, as the ε33 column's
// test (condense_longitudinal_test.cpp); reciprocity (AT, yT, CT against the ΔT row) to the
// elimination's round-off, 1e-9 as there. Strain-driven, the stress-driven strain gives its σ̄
// back, and σ33 is the energy's derivative in ε33 with ΔT held (the CT ε33 ΔT term).
TEST(Thermal, TheExactLawCarriesTheTemperatureChange) {
  for (const Macro macro : {Macro::full, Macro::transverse}) {
    Scene scene = thermal_scene(Boundary::periodic, Eigen::Vector2d(0.07, -0.04));
    scene.load.macro = macro;
    scene.load.delta_T = 0;
    validate(scene);
    const mesh::Mesh m = mesh::build_mesh(scene.geometry);
    ContactSolver solver(m, scene);
    const law::CondensedCell cell = condense(solver.setup());
    ASSERT_EQ(cell.thermal, 1);
    ASSERT_EQ(cell.longitudinal, macro == Macro::full ? 1 : 0);
    EXPECT_EQ(law::consistency_problem(cell), "");
    EXPECT_LE(cell.reciprocity_error, 1e-9);
    law::CellEvaluator law(cell);
    const double eps33_max = macro == Macro::full ? 2e-3 : 0.0;
    for (const auto& [sigma, eps33, delta_T] : {std::tuple{Eigen::Vector3d::Zero().eval(), 0.0, -100.0},
                                                std::tuple{Eigen::Vector3d(0.01, -0.004, 0.003), eps33_max, -100.0},
                                                std::tuple{Eigen::Vector3d(-0.006, 0.002, -0.001), -eps33_max, 50.0}}) {
      const MacroState state = cooled(sigma, delta_T, eps33);
      const Solution s = solver.solve_fixed(state, solver.intact());
      ASSERT_TRUE(s.converged()) << s.qp.message;
      law::CellHistory h = law.unloaded();
      const law::CellResponse r = law.at(state, h);
      ASSERT_TRUE(r.ok) << r.message;
      const Eigen::Vector3d expected = engineering_from_tensor(s.strain);
      EXPECT_LE((r.strain - expected).norm(), 1e-7 * expected.norm()) << sigma.transpose() << " ΔT " << delta_T;
      EXPECT_EQ(r.broken, 0);
      if (macro == Macro::full) {
        EXPECT_NEAR(r.stress_zz, s.average_stress_zz, 1e-7 * std::abs(s.average_stress_zz));
        law::CellHistory h2 = law.unloaded();
        const law::CellResponse back =
            law.at(MacroState::strain(r.strain).hold(MacroState::zz, eps33).hold(MacroState::dT, delta_T), h2);
        ASSERT_TRUE(back.ok) << back.message;
        EXPECT_LE((back.stress - sigma).norm(), 1e-9 * (sigma.norm() + std::abs(r.stress_zz)));
        const double step = 1e-7;
        law::CellHistory hp = law.unloaded(), hm = law.unloaded();
        const auto at_eps33 = [&](double e, law::CellHistory& hh) {
          return law.at(MacroState::strain(r.strain).hold(MacroState::zz, e).hold(MacroState::dT, delta_T), hh);
        };
        EXPECT_NEAR((at_eps33(eps33 + step, hp).energy - at_eps33(eps33 - step, hm).energy) / (2 * step),
                    back.stress_zz, 1e-6 * std::abs(back.stress_zz));
      }
    }
  }
}

// The cool-down and a load past the onset through the exact law's cascade and the full solver's,
// from the same states: the cool-down (ΔT alone) breaks nothing, the load then breaks bonds;
// after each, the broken pairs are the same and ε̄ agrees to 1e-7 (as above).
TEST(Thermal, TheExactLawsCascadeFromTheCoolDownIsTheSolvers) {
  Scene scene = thermal_scene(Boundary::periodic, Eigen::Vector2d(0.07, -0.04));
  scene.interface.normal_strength = 0.02;
  scene.interface.tangential_strength = 0.05;
  scene.load.delta_T = -20;
  validate(scene);
  const mesh::Mesh m = mesh::build_mesh(scene.geometry);
  ContactSolver solver(m, scene);
  const law::CondensedCell cell = condense(solver.setup());
  law::CellEvaluator law(cell);
  law::CellHistory h = law.unloaded();
  const Eigen::Vector3d N(1, 0.2, 0);
  const double onset = solver.debond_onset(N);
  ASSERT_TRUE(std::isfinite(onset) && onset > 0);
  feti::BondState bonds = solver.intact();
  for (const double t : {0.0, 1.5 * onset, 3 * onset}) {
    const Solution s = solver.solve(cooled(t * N, scene.load.delta_T), bonds);
    ASSERT_TRUE(s.converged()) << s.qp.message;
    bonds = s.bonds;
    const law::CellResponse r = law.at(cooled(t * N, scene.load.delta_T), h);
    ASSERT_TRUE(r.ok) << r.message;
    int solver_broken = 0;
    for (std::size_t p = 0; p < s.bonds.size(); ++p) solver_broken += !s.bonds[p];
    EXPECT_EQ(r.broken, solver_broken) << "t = " << t;
    if (t == 0) {
      EXPECT_EQ(r.broken, 0);
    } else {
      EXPECT_GE(r.broken, 1);
    }
    const Eigen::Vector3d expected = engineering_from_tensor(s.strain);
    EXPECT_LE((r.strain - expected).norm(), 1e-7 * expected.norm()) << "t = " << t;
  }
}

}  // namespace
}  // namespace dualcell::feti
