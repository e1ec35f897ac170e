#pragma once
// The constraint rows of Total FETI (docs/method.md §4): B u ≤ c (interface non-penetration) and
// B u = c (gluing, Dirichlet, periodicity), each row with the bounds of its multiplier.
//
//   row kind     | B row                               | multiplier bounds  (ℓ ≤ λ ≤ υ)
//   -------------+-------------------------------------+---------------------------------------
//   glue         | u_a,c − u_b,c            = 0        | free
//   dirichlet    | u_a,c                    = t·ū_a,c  | free (ū prescribed, t the load factor; 0 but for edges)
//   periodic     | u_r,c − u_l,c − (H Δx)_c = 0        | free (H: macro strain DOFs)
//   normal       | n·u_f − n·u_m            ≤ 0        | λ ≥ 0, bonded: λ ≥ −s_n·L_p
//   tangential   | t·u_f − t·u_m            = 0        | bonded only: −s_t·L_p ≤ λ ≤ s_t·L_p
//
// n is the fibre's outward normal at the node from the exact circle, t = (−n_y, n_x), L_p the
// interface length of pair p, ∫ φ_p ds over its rim edges (half its two chords for p1), s_n
// and s_t the strengths per unit length: nodal bounds consistent with nodal forces, so results
// do not depend on the mesh degree. A scene without adhesion has no tangential rows; one cell
// has no glue rows.
//
// Rows are scaled by w_r = sqrt(harmonic mean of the Young's moduli the row couples) so that
// F = B K⁺ Bᵀ has a diagonal of the same order (that of the matrix, ~1/E_m) whatever the
// stiffness contrast; the stored B, c and bounds are the scaled ones (λ_scaled = λ / w,
// force = w·λ_scaled).
#include <Eigen/SparseCore>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/scene.hpp"
#include "mesh/mesh.hpp"
#include "primal/antiplane.hpp"

namespace dualcell::feti {

enum class RowKind : std::uint8_t { glue, dirichlet, periodic, normal, tangential };
const char* to_string(RowKind kind);
// Normal and tangential rows: an interface pair's, with the bounds of the bond rule
// (law/bond.hpp); the others are equalities that hold the structure together.
inline bool is_interface(RowKind kind) { return kind == RowKind::normal || kind == RowKind::tangential; }

// Bond state of every interface pair: true = the adhesive bond holds (normal and tangential).
// Breaks are irreversible along a load path; without adhesion every entry is false.
using BondState = std::vector<std::uint8_t>;
BondState intact_bonds(const mesh::Mesh& mesh, const Interface& interface);

struct Constraints {
  // B over the global DOFs (2·n_nodes, plus 3 macro-strain DOFs εxx, εyy, γxy at the end for
  // the periodic boundary), scaled rows.
  Eigen::SparseMatrix<double, Eigen::RowMajor> B;
  Eigen::VectorXd c;       // right-hand side (scaled) at load factor 1: B u = t·c (docs/method.md §15)
  Eigen::VectorXd lower;   // ℓ (scaled), −inf where free
  Eigen::VectorXd upper;   // υ (scaled), +inf where free
  Eigen::VectorXd weight;  // w_r
  std::vector<RowKind> kind;
  std::vector<int> pair;  // interface pair of normal/tangential rows, glue pair of glue rows, else −1
  int n_macro_dofs = 0;   // 3 with the periodic boundary, else 0
  int n_rows() const { return static_cast<int>(kind.size()); }
};

// Exact outward normal of the fibre at the fibre node of interface pair p.
Eigen::Vector2d interface_normal(const mesh::Mesh& mesh, int p);
// Interface length of each pair: L_p = ∫ φ_p ds over the rim (φ_p the shape function of the
// pair's node along the rim edges); for p1 half of its two neighbouring chords.
std::vector<double> interface_lengths(const mesh::Mesh& mesh);
// Each pair's strength along the fibres (the shear along z, docs/method.md §16a): its in-plane
// tangential row's intact bound, s_t L (law::bond::bounds); 0 without a tangential strength.
std::vector<double> shear_strengths(const mesh::Mesh& mesh, const Scene& scene);
// The tied pairs (bonded[p] ≠ 0) whose force along z, pair_forces(p), is at its strength ±strength[p]
// (law::bond::at_strength of an along_fibres row): the ties a round of the cascade along the
// fibres breaks, in the full solver's debond loop and in the one-body cascade below alike.
std::vector<int> ties_at_strength(const Eigen::VectorXd& pair_forces, const std::vector<char>& bonded,
                                  const std::vector<double>& strength);
// The one-body shear along the fibres at Γ with its debond cascade (law::bond::cascade): the ties
// of `bonded` hold to `strength` (primal::longitudinal_shear_at), those at their strength break
// and the body is solved again until none is; `bonded` ends as the cascade leaves it. The
// sweep's /shear_check, and the tests' reference for the exact law's cascade along z.
primal::ShearResponse longitudinal_shear_cascade(const mesh::Mesh& mesh, const Scene& scene, std::vector<char>& bonded,
                                                 const Eigen::Vector2d& gamma, const std::vector<double>& strength);

// The mesh sides of the edges left, right, bottom, top (the order of edge_names).
extern const std::array<int, 4> edge_sides;
// A node of the mesh at x (within node_reach of the block's size), for supports, point loads and the
// watch point of Boundary::edges; an InputError naming where it was written (or `what`) and x
// when there is none.
int node_at(const mesh::Mesh& mesh, const Eigen::Vector2d& x, const std::string& where, const char* what);
// node_at for every position `loads` names (supports, point loads, the watch point): a scene's
// positions checked against its mesh while the inputs are read, before any work.
void check_positions(const mesh::Mesh& mesh, const EdgeLoads& loads);

Constraints build_constraints(const mesh::Mesh& mesh, const Scene& scene, const BondState& bonds);

}  // namespace dualcell::feti
