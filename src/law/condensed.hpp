#pragma once
// The exact law of a cell: the cell condensed onto its interface rows (docs/method.md §16a).
//
//   symbol | variable              | meaning
//   -------+-----------------------+----------------------------------------------------------
//   |Ω|    | CondensedCell::volume | the cell's area (the block's, ex × ey cells)
//   S₀     | S0                    | compliance of the open cell: every interface row removed
//   H      | H                     | interface flexibility: the opening of row i per unit force
//          |                       | pair at row j, the open cell responding
//   Y      | Y                     | the opening of each interface row per unit macro stress
//   G      | G                     | the fibres' equilibrium rows on the interface forces: G p = 0
//   p      | CellResponse::forces  | interface forces (physical units: force per unit thickness)
//
// Stress-driven, p = argmin ½pᵀHp − pᵀYσ̄ over the admissible set, then ε̄ = S₀σ̄ − Yᵀp/|Ω|;
// strain-driven, (σ̄, p) = argmin ½zᵀ𝓗z − |Ω|ε̄·σ̄ with z = (σ̄, p) and
// 𝓗 = [|Ω|S₀ −Yᵀ; −Y H]. The admissible set: G p = 0 and per row the bounds of its bond state
// (bonded: −s_n L ≤ p_n, |p_t| ≤ s_t L; broken: 0 ≤ p_n, p_t = 0). Strains use engineering
// shear, ε̄ = (εxx, εyy, γxy), so that σ̄·ε̄ is the work per unit volume.
//
// History is the bond state: an evaluation solves, breaks every bonded row that ends at its
// strength (normal and tangential rows of the pair together), and solves again until nothing
// more breaks: the debond cascade of the cell, carried to the next evaluation of the same point.
#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "core/macro_state.hpp"
#include "law/bond.hpp"
#include "qp/dense_qp.hpp"

namespace dualcell::law {

// The most interface rows a cell's law has: the condensation forms dense matrices of its rows
// (feti::max_condensed_rows), and each evaluation factorises one of that size (8·n² bytes, 72 MB
// at 3000 rows; about a second). A law file that declares more is refused before it is read.
inline constexpr int max_cell_rows = 3000;

struct CondensedCell {
  int n_macro = 3;  // 3: σ̄ = (σxx, σyy, σxy); 2: (σxx, σyy), the symmetry boundary (no shear)
  double volume = 0;
  Eigen::MatrixXd S0;  // n_macro × n_macro, symmetric positive definite
  Eigen::MatrixXd Y;   // n_rows × n_macro
  Eigen::MatrixXd H;   // n_rows × n_rows, symmetric positive semidefinite
  Eigen::MatrixXd G;   // n_fibre_modes × n_rows
  // Per interface row: tangential (1) or normal (0), its pair, the bounds of p while the pair
  // is bonded and after it broke.
  std::vector<std::uint8_t> tangential;
  std::vector<int> pair;
  Eigen::VectorXd lower_bonded, upper_bonded, lower_broken, upper_broken;
  int n_pairs = 0;
  std::vector<std::uint8_t> bonded;  // the bond state of the unloaded cell, per pair
  // Generalised plane strain (docs/method.md §16a, "The strain along the fibres"): with
  // longitudinal = 1 the cell also takes a uniform strain ε33 along the fibres. A33 (n_macro × 1)
  // is the open cell's ε̄ per unit ε33 (σ̄ = 0), C33 (1 × 1) its σ33 per unit ε33, y33
  // (n_rows × 1) the interface rows' opening per unit ε33: the rows' right-hand side becomes
  // Y σ̄ + y33 ε33, ε̄ gains A33 ε33, and σ33 = −A33·σ̄ + C33 ε33 + y33·p/|Ω|. With 0 the three
  // are empty: plane strain only (a scene's [load] macro = "transverse", a cell on a basis).
  int longitudinal = 0;
  Eigen::MatrixXd A33, C33, y33;
  // A temperature change ΔT from the stress-free state (docs/theory/model.md §1a): with
  // thermal = 1 (both phases expand) the law is affine in it, a column like ε33's. AT (n_macro ×
  // 1) is the open cell's ε̄ per kelvin (σ̄ = 0), yT (n_rows × 1) the rows' opening per kelvin,
  // CT (longitudinal × 1) σ33 per kelvin at ε33 = 0: the rows' right-hand side gains yT ΔT, ε̄
  // gains AT ΔT and σ33 gains CT ΔT. With 0 they are empty (phases without expansion).
  int thermal = 0;
  Eigen::MatrixXd AT, CT, yT;
  // Longitudinal shear (docs/method.md §16a, "The shear along the fibres"): with shear = 2 the
  // cell also takes the macro shears Γ = (γxz, γyz) along the fibres, the antiplane problem
  // condensed onto the pairs. D0z (2 × 2) is ⟨τ⟩ = (τxz, τyz) per unit Γ of the open cell (every
  // pair free to slip along z, the fibres as holes). Where bonds carry shear (shear_rows > 0; 0
  // without adhesion, when ⟨τ⟩ = D0z Γ whatever the state), row r is a force q_r along z of the
  // pair pair_z[r] (the exact law: one row per pair, pair_z[r] = r; a small cell with a fuse:
  // its one pair's facet rows, law/fused_cell.hpp): Yz (rows × 2) the open cell's jump of w per
  // unit Γ, Hz (rows × rows) the jump per unit force, Gz (one row per floating fibre) its
  // forces' sum, strength_z (rows) the bound |q_r| ≤ strength_z while the pair is bonded (0
  // once it broke). Then
  //   q = argmin ½ qᵀHz q − qᵀYz Γ over Gz q = 0 and the bounds,  ⟨τ⟩ = D0z Γ + Yzᵀq/|Ω|.
  // In-plane and antiplane do not share a stiffness (isotropic phases): only the bond state.
  int shear = 0, shear_rows = 0;
  Eigen::MatrixXd D0z, Yz, Hz, Gz;
  Eigen::VectorXd strength_z;
  std::vector<int> pair_z;

  // What the condensation measured: the asymmetry of 𝓗 before it was symmetrised (reciprocity,
  // relative), its seconds, and the applications of B K⁺ it took (F itself is summed from the
  // subdomains' blocks F_s, DualProblem::explicit_F).
  double reciprocity_error = 0;
  double seconds = 0;
  long operator_applications = 0;

  int n_rows() const { return static_cast<int>(pair.size()); }
  bond::Kind kind(int r) const { return tangential[r] ? bond::Kind::tangential : bond::Kind::normal; }
  bond::Bounds bonded_bounds(int r) const { return {lower_bonded(r), upper_bonded(r)}; }
  bond::Bounds broken_bounds(int r) const { return {lower_broken(r), upper_broken(r)}; }
  bond::Bounds bonded_bounds_z(Eigen::Index q) const { return bond::intact_along_fibres(strength_z(q)); }
  bool adhesion() const;
  // Bytes of the arrays (every array member of law/condensed_members.hpp).
  std::size_t bytes() const;
};

// 𝓗 = [|Ω|S₀ −Yᵀ; −Y H], the energy of the strain-driven law (docs/method.md §16a).
Eigen::MatrixXd energy_matrix(const CondensedCell& cell);

// Empty when the cell is usable (sizes agree, everything finite, S₀ and H symmetric, bounds
// ordered with 0 within them: the rules of its member table, law/condensed_members.hpp, and the
// broken bounds the bond rule's; the volume and every matrix's largest entry within 10^±100; 𝓗
// positive definite on G p = 0, so the law is convex); otherwise what is wrong, "member: what"
// where one member is.
std::string consistency_problem(const CondensedCell& cell);

// One unit of material that follows the exact law: its bond state and the active set of its
// last evaluation (the warm start of the next).
struct CellHistory {
  std::vector<std::uint8_t> bonded;  // per pair
  std::vector<qp::Bound> active;     // per unknown of the last QP (empty: none yet)
  std::vector<qp::Bound> active_z;   // the same for the shear rows' QP
};

// What an evaluation does with the bonds: `cascade` breaks every bonded row that reaches its
// strength and solves again (the history moves on); `held` keeps the bond state as it is, a
// bonded row at its strength then carries its strength and no more (a trial state, e.g. a
// Newton iterate of a structure, which must not break anything); `lifted` is the intact cell
// with the strengths of its bonded rows removed (linear in the load: the onset's scaling).
enum class BondMode { cascade, held, lifted };

struct CellResponse {
  Eigen::Vector3d stress = Eigen::Vector3d::Zero();   // σ̄ (σxy = 0 with n_macro = 2)
  Eigen::Vector3d strain = Eigen::Vector3d::Zero();   // ε̄, engineering shear (γxy NaN with n_macro = 2)
  Eigen::Matrix3d tangent = Eigen::Matrix3d::Zero();  // dσ̄/dε̄, symmetric (shear NaN with n_macro = 2)
  Eigen::VectorXd forces;                             // p
  // Strain-driven: the strain energy per unit volume, W(ε̄) = ε̄·σ̄ − ½zᵀ𝓗z/|Ω| (the value of
  // the QP, Legendre-transformed; ∂W/∂ε̄ = σ̄). 0 when stress-driven.
  double energy = 0;
  // The largest force of a bonded row over its strength (0 … 1; 1: at its strength), over the
  // bonded rows of the history the evaluation ends with.
  double strength_use = 0;
  // With ε33 (the cell's longitudinal data): σ33, and the tangent's column dσ̄/dε33 (equal to
  // the row dσ33/dε̄, by symmetry) and dσ33/dε33 (strain-driven; NaN stress-driven). NaN
  // without ε33 data.
  double stress_zz = std::numeric_limits<double>::quiet_NaN();
  Eigen::Vector3d tangent_zz = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
  double tangent_zz_zz = std::numeric_limits<double>::quiet_NaN();
  // With the shear along the fibres (the cell's shear = 2): ⟨τ⟩ = (τxz, τyz) at Γ = (γxz, γyz),
  // its tangent dτ/dΓ (symmetric; in-plane and antiplane share no stiffness, so the 6 × 6
  // tangent has no other coupling to them), and the shear rows' forces q. NaN without the data.
  Eigen::Vector2d shear_z = Eigen::Vector2d::Constant(std::numeric_limits<double>::quiet_NaN());
  Eigen::Matrix2d tangent_z = Eigen::Matrix2d::Constant(std::numeric_limits<double>::quiet_NaN());
  Eigen::VectorXd forces_z;
  int broken = 0;        // pairs broken after this evaluation
  int newly_broken = 0;  // of which broke in it
  int iterations = 0;    // active-set subproblems, over all rounds
  int factorisations = 0;
  int updates = 0;  // new free sets solved by bordering a kept factorisation
  bool ok = false;
  std::string message;  // why not, when not ok
};

// The whole ply's response (a cell with the strain and the shears along the fibres) in the law's
// order (xx, yy, xy, zz, xz, yz): σ̄, σ33 and ⟨τ⟩; and the 6 × 6 tangent, in-plane and ε33
// coupled, the shears along the fibres on their own (no stiffness couples them to the rest).
Eigen::Matrix<double, 6, 1> ply_stress(const CellResponse& r);
Eigen::Matrix<double, 6, 6> ply_tangent(const CellResponse& r);

// Evaluates one CondensedCell; holds the energy matrix 𝓗 and the QP workspaces (not thread-safe:
// one evaluator per thread).
class CellEvaluator {
 public:
  // `updates`: how its QPs solve a new free set (qp/dense_qp.hpp): bordered on the kept
  // factorisation (the default) or factorised each time (the reference, for comparison).
  explicit CellEvaluator(const CondensedCell& cell,
                         qp::DenseActiveSet::Updates updates = qp::DenseActiveSet::Updates::bordered);
  const CondensedCell& cell() const { return cell_; }
  // The unloaded cell's history.
  CellHistory unloaded() const;
  // The response to the macro state s (core/macro_state.hpp) from the history h, which is updated
  // (breaks are irreversible): its in-plane part a macro stress σ̄ (stress-driven, the bonds'
  // cascade) or a macro strain ε̄ (strain-driven, engineering shear, with `bonds`); with a strain
  // ε33 along the fibres (the cell must carry its longitudinal data when ε33 ≠ 0) and the shears
  // Γ = (γxz, γyz) along them (the cell's shear data when Γ ≠ 0; with it the shear rows join the
  // cascade: a pair at its strength along z breaks as a whole too), and with a temperature
  // change ΔT (the cell's thermal data when ΔT ≠ 0). A state the cell cannot take (a mixed
  // in-plane part, a stress along the fibres, data it does not have) is not ok, with the reason.
  CellResponse at(const MacroState& s, CellHistory& h, BondMode bonds = BondMode::cascade);
  // The in-plane state alone: at(MacroState::stress(sigma)), at(MacroState::strain(strain)).
  CellResponse at_stress(const Eigen::Vector3d& sigma, CellHistory& h) { return at(MacroState::stress(sigma), h); }
  CellResponse at_strain(const Eigen::Vector3d& strain, CellHistory& h, BondMode bonds = BondMode::cascade) {
    return at(MacroState::strain(strain), h, bonds);
  }
  // The load factor s* at which the first bond of the unloaded cell breaks under s·σ̄ (+inf
  // without adhesion or when no bond ever reaches its strength along σ̄): the bonded cell with
  // its strengths lifted is homogeneous of degree one in σ̄, so s* = min over bonded rows of
  // bound/p(σ̄).
  double onset(const Eigen::Vector3d& sigma);
  // A load factor along σ̄ at which the intact cell holds every bond: half its onset s*, or 1
  // where it has none (no adhesion, no bond ever at its strength, or the onset's QP failed).
  double bonded_load(const Eigen::Vector3d& sigma);

 private:
  // What a state holds beside its in-plane part: ε33, the shears Γ along the fibres and ΔT.
  struct Held {
    double eps33 = 0;
    Eigen::Vector2d gamma = Eigen::Vector2d::Zero();
    double delta_T = 0;
  };
  template <class Solve>
  CellResponse cascade(CellHistory& h, BondMode bonds, const Eigen::Vector2d& gamma, Solve&& solve);
  void set_bounds(const std::vector<std::uint8_t>& bonded, int offset, bool lifted = false);
  // The largest strength use of the bonded rows' forces p and shear rows' forces q (empty: none).
  double strength_use(const Eigen::VectorXd& forces, const Eigen::VectorXd& forces_z,
                      const std::vector<std::uint8_t>& bonded) const;
  void check_inputs(const MacroState& s, CellResponse& out) const;
  CellResponse stress_driven(const Eigen::Vector3d& sigma, CellHistory& h, const Held& held);
  CellResponse strain_driven(const Eigen::Vector3d& strain, CellHistory& h, BondMode bonds, const Held& held);
  // The shear along the fibres at gamma for the bonds of h: the shear rows' QP (where the cell
  // has them), ⟨τ⟩ and its tangent into r; false, with r.message, when the QP did not converge.
  bool solve_shear(const Eigen::Vector2d& gamma, CellHistory& h, bool lifted, CellResponse& r);
  // σ33 of a solution (σ̄, p) at the held ε33 and ΔT, when the cell has the data.
  void set_stress_zz(const Held& held, CellResponse& out) const;
  // One QP of the cascade with its linear term b and bounds: its counts into r, its solution into
  // x; false, with r.message, when it did not converge.
  bool solve_qp(qp::DenseActiveSet& qp, const Eigen::VectorXd& b, const Eigen::VectorXd& lower,
                const Eigen::VectorXd& upper, std::vector<qp::Bound>& active, CellResponse& r, Eigen::VectorXd& x);

  const CondensedCell& cell_;
  const Eigen::MatrixXd energy_;       // 𝓗
  const Eigen::MatrixXd C_strain_;     // [0 G]
  Eigen::VectorXd lower_, upper_, b_;  // the QP's bounds and linear term
  // One QP per problem (qp::DenseActiveSet binds its matrices): stress-driven (H, G), strain-driven
  // (𝓗, [0 G]) and the onset's (H, G with the strengths lifted).
  qp::DenseActiveSet stress_qp_, strain_qp_, onset_qp_;
  qp::DenseActiveSet shear_qp_;              // the shear rows' (Hz, Gz); empty without them
  Eigen::VectorXd lower_z_, upper_z_, b_z_;  // its bounds and linear term
  std::vector<qp::Bound> onset_active_;      // the warm start of the next onset
  // The last tangents and the factorisation they came from: the same factorisation (the same
  // free set) gives the same tangent, so a warm evaluation does not solve for it again.
  Eigen::Matrix3d stress_tangent_, strain_tangent_;
  Eigen::Vector3d strain_tangent_zz_;
  double strain_tangent_zz_zz_ = 0;
  long stress_tangent_of_ = -1, strain_tangent_of_ = -1;
  Eigen::Matrix2d shear_tangent_;
  long shear_tangent_of_ = -1;
};

}  // namespace dualcell::law
