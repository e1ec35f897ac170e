#pragma once
// The compact law of a cell with adhesion as a small cell (docs/method.md §16d): the bonded cell
// exactly, its onset exactly, and from the first break on a small cell of the debonded cell.
//
// Below its onset a bonded cell is linear, ε̄ = S_b σ̄, and each bond force is linear in σ̄: the
// bond reaches its strength where g_k·σ̄ = 1 (a facet of the onset polytope, law/onset.hpp). The
// compact law keeps S_b and the facets, and once a bond breaks it switches for good to a cell
// without bonds of m rows (fit/small_cell.hpp), fitted to the exact law past the fuse. It is one
// CondensedCell with one pair, so that every evaluator of the exact law (the fit's checks,
// dualcell-law, the structures, the umat) takes it with its history, the pair's bond state:
//
//   rows | kind       | bonded bounds | broken bounds | what they are
//   -----+------------+---------------+---------------+-------------------------------------------
//   b    | tangential | (−∞, 1]       | [0, 0]        | one per onset facet kept: p_b = G σ̄ bonded
//   c    | `after`'s  | [0, 0]        | `after`'s     | the small cell's rows past the fuse
//        | (normal)   |               | ([0, ∞))      |
//
//   G (F × n_macro)  the facets g_k kept, Δ = |Ω|(S₀ − S_b), G = Q R (thin QR),
//   H_bb = Q R⁻ᵀ Δ R⁻¹ Qᵀ + c (I − Q Qᵀ),   Y_b = H_bb G,
//   (H_cc, Y_c) the small cell's,   H_bc = Y_b A⁻¹ Y_cᵀ with A = |Ω| S₀.
//
// Bonded, the c rows are held at 0 and p_b = H_bb⁻¹ Y_b σ̄ = G σ̄, so row k reaches its bound 1
// exactly on facet k, and ε̄ = S₀σ̄ − Y_bᵀ p_b/|Ω| = (S₀ − Gᵀ H_bb G/|Ω|) σ̄ = S_b σ̄. Broken, the b
// rows are held at 0 and what remains is the small cell. H_bc is seen by neither state; it makes
// the Schur complement of 𝓗 = [A −Yᵀ; −Y H] on A block diagonal, [H_bb − Y_b A⁻¹ Y_bᵀ, 0; 0,
// H_cc − Y_c A⁻¹ Y_cᵀ], each block positive definite (|Ω|S_b and the small cell's own 𝓗), so the
// law is convex in each state and the cell passes consistency_problem.
#include <Eigen/Core>

#include "law/condensed.hpp"
#include "law/cone_check.hpp"

namespace dualcell::law {

// The cell with every pair broken: its bonded bounds the broken ones (contact rows, frictionless),
// no adhesion left.
CondensedCell debonded_cell(const CondensedCell& cell);

// The bonded cell below its onset: S_b (n_macro × n_macro) and, per strength bound of a bonded
// row, the facet g with g·σ̄ = 1 where the row reaches it (candidates × n_macro), from n_macro
// solves of the exact law at unit stresses (each at half its onset: every bond holds, so the
// response is linear). Throws std::invalid_argument where a solve fails or breaks a bond.
// With the strain along the fibres (cell.longitudinal = 1) the load is s = (σ̄, ε33): each facet
// has a fourth entry (g_k·s = 1) and the bonded cell's ε33 parts are A33_b (ε̄ per unit ε33 at
// σ̄ = 0) and C33_b (σ33 per unit ε33), from one more solve at σ̄ = 0. With shear rows, the bonded
// cell's shear along the fibres τ = Dz Γ and per strength bound of a bonded shear row the facet
// h with h·Γ = 1 where it reaches it (two solves at unit Γ, strengths lifted).
struct BondedCell {
  Eigen::MatrixXd S;       // S_b
  Eigen::MatrixXd facets;  // every candidate facet g_k (candidates × (n_macro + longitudinal))
  Eigen::VectorXd A33;     // A33_b (n_macro; empty without ε33)
  double C33 = 0;          // C33_b
  Eigen::Matrix2d Dz = Eigen::Matrix2d::Zero();
  Eigen::MatrixXd facets_z;  // candidates × 2 (empty without shear rows)
};
BondedCell bonded_cell(const CondensedCell& cell);

struct FusedCell {
  CondensedCell cell;                        // the compact law, F + m rows, one pair
  int facets = 0;                            // F: the onset polytope's facets
  int candidate_facets = 0;                  // of the bonds' strength bounds (the others are never reached first)
  double onset_error = 0;                    // the kept facets' onset against all bounds', the largest relative
                                             // difference over onset_check_directions directions (round-off)
  int facets_z = 0, candidate_facets_z = 0;  // the same along z: the shear rows kept (F_z)
};
// A facet within this (relative to the largest) of the hull of the others and the origin is one
// of them: its onset differs by at most as much.
inline constexpr double facet_tolerance = 1e-10;
inline constexpr int onset_check_directions = 30001;

// The compact law of `cell` (with adhesion, linear below its onset) with `after`, a cell without
// adhesion and with the cell's n_macro, volume and S₀ (a small cell; or debonded_cell(cell), whose
// equality rows G then act on the c rows), past the fuse. A cell with the strain along the fibres
// gives it the 4-dimensional onset and bonded law in s = (σ̄, ε33) (`after` then carries the same
// A33 and C33, and its own y33); a cell with the shears along the fibres gives it its open D0z,
// and where its bonds carry shear the bonded Dz and the shear onset as F_z facet rows of the one
// pair (docs/method.md §16d): past the fuse the shear is the open cell's, D0z.
// Throws std::invalid_argument where the cell has no adhesion, `after` does not fit it, or the
// kept facets do not span the macro stresses (the onset is unbounded in some direction).
FusedCell cell_with_fuse(const CondensedCell& cell, const CondensedCell& after);

// The compact law with a fuse along the exact law's cascade paths (sample_cell_past_fuse): per
// direction, from the intact cell, strain-driven at each exact strain of the path in turn (its
// bonds breaking where they reach their strength) and at the last; the direction's error the
// largest over its path, relative to the exact stress at each point.
ConeCheck check_along_fuse_paths(const CondensedCell& fused, const CellSample& past_fuse);

}  // namespace dualcell::law
