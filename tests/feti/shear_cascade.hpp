#pragma once
// The debond cascade along z of a full periodic cell's exact law against an independent one
// (docs/method.md §16a): the one-body antiplane solve with the bonded pairs tied, each tie holding
// to its strength and slipping past it (primal::longitudinal_shear_at with the strengths: the
// bounds of the law's shear rows), the ties at their strength broken by the same bond rule and
// the body solved again until none is. Along a path of growing Γ (half, 1.2, 2 and 4 times the
// first break's along `direction`) the law's forces equal the ties' while bonded, and at every
// step the same pairs break and ⟨τ⟩ agrees; `tolerance` relative (two exact routes: the
// condensation's and the factorisations' round-off). Returns the pairs broken at the end.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <vector>

#include "feti/constraints.hpp"
#include "law/condensed.hpp"
#include "primal/antiplane.hpp"

namespace dualcell::testing {

inline int expect_the_one_body_cascade(const mesh::Mesh& mesh, const Scene& scene, const law::CondensedCell& cell,
                                       const Eigen::Vector2d& direction, double tolerance) {
  law::CellEvaluator law(cell);
  std::vector<double> strength(cell.strength_z.data(), cell.strength_z.data() + cell.strength_z.size());
  law::CellHistory h0 = law.unloaded();
  const law::CellResponse small =
      law.at(MacroState::strain(Eigen::Vector3d::Zero()).hold_shear(1e-3 * direction), h0, law::BondMode::held);
  std::vector<char> bonded(cell.bonded.begin(), cell.bonded.end());
  const primal::ShearResponse tied =
      primal::longitudinal_shear_at(mesh, scene.fibre, scene.matrix, bonded, 1e-3 * direction, strength);
  EXPECT_LE((small.forces_z - tied.pair_forces).norm(), tolerance * tied.pair_forces.cwiseAbs().maxCoeff());
  EXPECT_LE((small.shear_z - tied.tau).norm(), tolerance * tied.tau.norm());
  const double first = 1e-3 / small.strength_use;  // the load factor of the first break along the direction
  law::CellHistory h = law.unloaded();
  int broken = 0;
  for (const double factor : {0.5, 1.2, 2.0, 4.0}) {
    const Eigen::Vector2d gamma = factor * first * direction;
    const law::CellResponse r = law.at(MacroState::strain(Eigen::Vector3d::Zero()).hold_shear(gamma), h);
    EXPECT_TRUE(r.ok) << r.message;
    const primal::ShearResponse one_body = feti::longitudinal_shear_cascade(mesh, scene, bonded, gamma, strength);
    for (std::size_t q = 0; q < bonded.size(); ++q) EXPECT_EQ(h.bonded[q] != 0, bonded[q] != 0) << factor << " " << q;
    EXPECT_LE((r.shear_z - one_body.tau).norm(), tolerance * one_body.tau.norm()) << factor;
    broken = r.broken;
  }
  return broken;
}

}  // namespace dualcell::testing
