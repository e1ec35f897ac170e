#pragma once
// Longitudinal (antiplane) shear of a periodic cell (docs/method.md §3b): the displacement w(x, y)
// along the fibres under a macro shear Γ = (γxz, γyz), w = Γ·x + w̃ with w̃ periodic, the shear
// stress τ = (τxz, τyz) = μ ∇w in each phase and div τ = 0. A bonded interface pair ties w across
// the rim; a broken pair (and frictionless contact, which carries no shear along z) leaves w free
// to jump, so no shear crosses it. The problem is linear for a given bond state and scalar: it is
// solved as one body (the mesh's points merged with their periodic partners and, where bonded,
// their interface partners; one held value per piece left floating, w̃ being defined up to a
// constant on each), K = Σ ∫ μ ∇φᵀ∇φ dA by the 6-point rule, one CHOLMOD factorisation for both
// unit shears. It is the 2D conductivity problem, so Keller's theorem holds for it.
#include <Eigen/Core>
#include <vector>

#include "core/scene.hpp"
#include "mesh/mesh.hpp"

namespace dualcell::primal {

struct LongitudinalShear {
  // ⟨τ⟩ = G Γ, symmetric: the cell's longitudinal shear moduli, G(0, 0) = G_xz and G(1, 1) = G_yz
  // (a ply's G12 and G13, its axis 1 along the fibres, z here).
  Eigen::Matrix2d G = Eigen::Matrix2d::Zero();
  // Per node, w̃ of the unit shears Γ = (1, 0) and (0, 1) (columns): w = Γ·x + w̃ Γ.
  Eigen::MatrixXd w_tilde;
};

// `bonded`: per interface pair whether its bond holds (size mesh.interface_pairs.size()); empty:
// every pair bonded. Materials: the scene's fibre and matrix (shear modulus E/(2(1+ν))).
// Throws std::runtime_error when the factorisation fails.
LongitudinalShear longitudinal_shear(const mesh::Mesh& mesh, const Material& fibre, const Material& matrix,
                                     const std::vector<char>& bonded = {});

// The response at Γ of the bond state `bonded` (one entry per pair): ⟨τ⟩ and each bonded pair's
// force along z, the tie's (the internal force ∫ μ ∇φ·(Γ + ∇w̃) dA of the fibre's elements at
// the pair's place, its periodic images included, with the sign of the condensed law's force q;
// 0 for a broken pair). With `strength` (per pair) a tie holds up to its strength and slips past
// it, carrying ±strength with a jump of that sign (the bounds the exact law's shear rows have,
// found by an active set of one linear solve per change); empty: ties without a bound. For the
// debond cascade along z (the caller breaks what is at its strength and asks again).
struct ShearResponse {
  Eigen::Vector2d tau = Eigen::Vector2d::Zero();
  Eigen::VectorXd pair_forces;
};
ShearResponse longitudinal_shear_at(const mesh::Mesh& mesh, const Material& fibre, const Material& matrix,
                                    const std::vector<char>& bonded, const Eigen::Vector2d& gamma,
                                    const std::vector<double>& strength = {});

// The longitudinal shear condensed onto the interface pairs (docs/method.md §16a, "The shear along the fibres"), the
// exact law of every bond state at once. The open cell (every pair free to jump, each fibre floating along z) has w̃ =
// K⁺(f Γ − Jᵀq) under pair forces q (J: the jump of w̃ across each pair, fibre minus matrix); a bond state ties the
// jumps of its bonded pairs, and the forces that do it solve
//   q = argmin ½ qᵀH q − qᵀY Γ  over  G q = 0 (and the bounds of each pair's bond),
// with ⟨τ⟩ = D0 Γ + Yᵀq/|Ω|. Without bonds q = 0: the open cell, fibres as holes.
struct CondensedShear {
  Eigen::Matrix2d D0 = Eigen::Matrix2d::Zero();  // ⟨τ⟩ per unit Γ of the open cell (energy form)
  Eigen::MatrixXd Y;                             // pairs × 2: J K⁺ f, the open cell's jump at each pair per unit Γ
  Eigen::MatrixXd H;  // pairs × pairs: J K⁺ Jᵀ, the jump at each pair per unit pair force
  Eigen::MatrixXd G;  // one row per floating piece (a fibre): the sum of its pairs' forces
};

// With rows = false only D0 (a cell without bonds needs nothing else). Throws
// std::runtime_error when the factorisation fails.
CondensedShear condense_longitudinal_shear(const mesh::Mesh& mesh, const Material& fibre, const Material& matrix,
                                           bool rows = true);

}  // namespace dualcell::primal
