#pragma once
// Hill's exact relations (docs/method.md §3a), a check shared by the tests of generalised plane
// strain on mapped cells and on random RVEs: for two phases bonded in any geometry, isotropic or
// transversely isotropic about the fibres' axis, E1 and ν12 follow from the transverse
// (plane-strain) bulk modulus k23 of the same cell:
//   E1  = ⟨E_L⟩ + 4 (ν_f − ν_m)² / (1/k_f − 1/k_m)² · (⟨1/k⟩ − 1/k23),
//   ν12 = ⟨ν⟩ + (ν_f − ν_m) / (1/k_m − 1/k_f) · (⟨1/k⟩ − 1/k23),
// ν = ν_LT, k = (C11 + C12)/2 the phase's plane-strain bulk modulus (λ + μ isotropic), ⟨·⟩ the
// volume average. 1/k23 = ε̄xx + ε̄yy under σ̄ = (1, 1, 0), ε33 = 0; E1 = ⟨σ33⟩ and
// ν12 = −(ε̄xx + ε̄yy)/2 under ε33 = 1, σ̄ = 0. The proof is a state of uniform strain (e, e, 0) in
// every element under ε33 = 1 and σ̄ = (s, s, 0), with e = −(C13_f − C13_m)/(2(k_f − k_m)) and
// s = 2 k_f e + C13_f: both phases then carry the same in-plane stress, so it solves the
// discrete problem exactly, whatever the mesh (fem::phase_stiffness gives C13, C33 and k).
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <string>

#include "fem/assembly.hpp"
#include "fem/element.hpp"
#include "feti/solver.hpp"

namespace dualcell::testing {

// The fibres' share of the block's area, from the elements themselves.
inline double fibre_fraction(const mesh::Mesh& m) {
  const fem::ElementStresses e = fem::element_stresses(m, {1, 0.3}, {1, 0.3}, Eigen::VectorXd::Zero(m.dim_u()));
  double fibre = 0;
  for (int t = 0; t < e.area.size(); ++t)
    if (m.subdomains[m.triangle_subdomain[t]].is_fibre) fibre += e.area(t);
  return fibre / e.area.sum();
}

// Checks the uniform state and both relations on the bonded, periodic cell (mesh, scene) to
// `tolerance` relative; `what` names the cell in the failures.
inline void expect_hill_relations(const mesh::Mesh& m, const Scene& scene, double tolerance, const std::string& what) {
  feti::ContactSolver solver(m, scene);
  const double vf = fibre_fraction(m), vm = 1 - vf;
  const fem::PhaseStiffness f = fem::phase_stiffness(scene.fibre), mx = fem::phase_stiffness(scene.matrix);
  const double kf = (f.D(0, 0) + f.D(0, 1)) / 2, km = (mx.D(0, 0) + mx.D(0, 1)) / 2;

  // The uniform state.
  const double e = -(f.C13 - mx.C13) / (2 * (kf - km)), s = 2 * kf * e + f.C13;
  const feti::Solution uniform =
      solver.solve_fixed(MacroState::stress(Eigen::Vector3d(s, s, 0)).hold(MacroState::zz, 1), solver.intact());
  ASSERT_TRUE(uniform.converged()) << what << ": " << uniform.qp.message;
  EXPECT_LE((uniform.strain - Eigen::Vector3d(e, e, 0)).norm(), tolerance * std::abs(e)) << what;
  const double zz = vf * (2 * f.C13 * e + f.C33) + vm * (2 * mx.C13 * e + mx.C33);
  EXPECT_NEAR(uniform.average_stress_zz, zz, tolerance * zz) << what;

  // k23, then E1 and ν12, against Hill's relations.
  const feti::Solution biaxial = solver.solve_fixed(Eigen::Vector3d(1, 1, 0), solver.intact());
  const feti::Solution axial =
      solver.solve_fixed(MacroState::stress(Eigen::Vector3d::Zero()).hold(MacroState::zz, 1), solver.intact());
  ASSERT_TRUE(biaxial.converged() && axial.converged()) << what;
  const double inv_k23 = biaxial.strain(0) + biaxial.strain(1);
  const double E1 = axial.average_stress_zz, nu12 = -(axial.strain(0) + axial.strain(1)) / 2;
  const double Ef = scene.fibre.axial_E(), Em = scene.matrix.axial_E();
  const double nuf = scene.fibre.axial_nu(), num = scene.matrix.axial_nu();
  const double excess = vf / kf + vm / km - inv_k23;  // ⟨1/k⟩ − 1/k23 ≥ 0 (Reuss)
  EXPECT_GT(excess, 0) << what;
  const double E1_hill =
      vf * Ef + vm * Em + 4 * (nuf - num) * (nuf - num) / ((1 / kf - 1 / km) * (1 / kf - 1 / km)) * excess;
  const double nu12_hill = vf * nuf + vm * num + (nuf - num) / (1 / km - 1 / kf) * excess;
  EXPECT_NEAR(E1, E1_hill, tolerance * E1_hill) << what;
  EXPECT_NEAR(nu12, nu12_hill, tolerance * nu12_hill) << what;
  // Hill's correction itself is not within the tolerance (the check could not tell otherwise).
  EXPECT_GT(E1 - (vf * Ef + vm * Em), 100 * tolerance * E1) << what;
}

}  // namespace dualcell::testing
