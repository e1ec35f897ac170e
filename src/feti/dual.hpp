#pragma once
// The dual problem of Total FETI (docs/method.md §6), for one set of
// constraints (one bond state):
//
//   F = B K⁺ Bᵀ,  d = B K⁺ f − c,  G = R̂ᵀ Bᵀ,  e = R̂ᵀ f
//   min ½ λᵀFλ − λᵀd   s.t.  Gλ = e,  ℓ ≤ λ ≤ υ
//
// made homogeneous by λ = λ₀ + x with λ₀ = Gᵀ(GGᵀ)⁻¹e (bounds shifted by −λ₀), and solved
// with the orthogonal projector P = I − Q, Q = Gᵀ(GGᵀ)⁻¹G, as min ½xᵀPFPx − xᵀP(d − Fλ₀)
// s.t. Qx = 0 (SMALBE, whose multiplier of Qx = 0 is μ) and the shifted bounds (MPRGP inside).
//
//   symbol | variable            | note
//   -------+---------------------+-----------------------------------------------------
//   B_i    | Local::B            | the rows of B touching subdomain i, local columns
//   R̂_i    | Local::R_hat        | the part of R_i that B sees: a fibre without adhesion
//          |                     | spins freely about its centre (normal rows cannot see
//          |                     | it), so that mode is dropped from G and recovered later
//   D      | G_row_scale_        | 1/‖row‖ of each row of G: the coarse solves use DG
//   GGᵀ    | GGt_                | (DG)(DG)ᵀ: small sparse SPD, CHOLMOD, factorised once per problem
//
// No matrix of size dim u or dim λ is ever dense: F and Q are applied as operators.
//
// Over the ranks of setup().group() (docs/method.md §16), λ and every vector of dim λ are
// replicated: each rank applies K⁺ and the preconditioner of the subdomains it owns, sums their
// rows into its part of the result, and one MPI_Allgatherv per application of F or M⁻¹ brings
// every rank every part, added in rank order. G, GGᵀ and the QP's vector work are the same on
// every rank, done in lockstep, so the ranks never disagree on λ.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

#include "core/fields.hpp"
#include "feti/constraints.hpp"
#include "feti/setup.hpp"
#include "linalg/sparse_cholesky.hpp"

namespace dualcell::feti {

// The joint null-mode search of the coarse matrices (GGᵀ here, G_E G_Eᵀ of the condensation):
// the eigenvectors of a small symmetric positive semidefinite A, split into those of its range
// and those of its null space. An eigenvalue at most null_mode_tolerance × the largest counts as
// zero (round-off of the sums that form A); the same cut says whether a combination of modes is
// seen by a set of rows (‖zᵀG‖ against ‖G‖).
inline constexpr double null_mode_tolerance = 1e-10;
struct NullSplit {
  Eigen::MatrixXd range, null;  // orthonormal columns
  double largest = 0;           // the largest eigenvalue of A
};
NullSplit split_null_space(const Eigen::MatrixXd& A);

// Wall time spent in apply_F (and d), apply_Q and apply_preconditioner (a profile for the
// performance report; one clock read per call, nothing per subdomain), and of that the time in
// the exchanges between ranks, their count and the bytes this rank received (zero on one rank).
struct OperatorProfile {
  double F = 0, Q = 0, preconditioner = 0;
  double communication = 0;
  long exchanges = 0;
  double bytes_received = 0;
  // Member by member (operator_profile_fields): a sum of profiles, and what was spent between
  // two readings of the same one.
  OperatorProfile& operator+=(const OperatorProfile& other);
  OperatorProfile operator-(const OperatorProfile& before) const;
};
// Its members, listed once (core/fields.hpp): walked by += and −, by solution.h5 (the seconds,
// unit "s", as /solver seconds_qp_<name>) and by the tests.
inline constexpr Field<OperatorProfile, double, long> operator_profile_fields[] = {
    {"F", &OperatorProfile::F, 0, "s"},
    {"Q", &OperatorProfile::Q, 0, "s"},
    {"preconditioner", &OperatorProfile::preconditioner, 0, "s"},
    {"communication", &OperatorProfile::communication, 0, "s"},
    {"exchanges", &OperatorProfile::exchanges},
    {"bytes_received", &OperatorProfile::bytes_received, 0, "bytes"},
};
inline OperatorProfile& OperatorProfile::operator+=(const OperatorProfile& other) {
  add_fields(operator_profile_fields, *this, other);
  return *this;
}
inline OperatorProfile OperatorProfile::operator-(const OperatorProfile& before) const {
  OperatorProfile out = *this;
  add_fields(operator_profile_fields, out, before, -1);
  return out;
}

class DualProblem {
 public:
  DualProblem(const FetiSetup& setup, Constraints constraints);
  DualProblem(const DualProblem&) = delete;
  DualProblem& operator=(const DualProblem&) = delete;

  struct Local {
    std::vector<int> rows;                           // global row indices, ascending
    Eigen::SparseMatrix<double, Eigen::RowMajor> B;  // rows.size() × n_dofs
    Eigen::MatrixXd R_hat;                           // n_dofs × r_i
    Eigen::MatrixXd V;                               // 3 × r_i: R_hat = R V
    int G_offset = 0;                                // first row of G for this subdomain
    // F_s = B_s K_s⁺ B_sᵀ (rows × rows, dense) where the subdomain applies F explicitly
    // (FloatingSubdomain::explicit_operator): the setup's F_intact without adhesion, else formed
    // here from K⁺(b, b) into F_own; null where implicit.
    const Eigen::MatrixXd* F = nullptr;
    Eigen::MatrixXd F_own;
    // Preconditioner row factors δ_ri / w_r² (see apply_preconditioner); empty without one.
    Eigen::VectorXd preconditioner_scale;
    // Where each of `rows` is summed in this rank's part of the exchange (owned subdomains only).
    std::vector<int> slot;
    // scratch for operator applications (no allocation per application); each subdomain's
    // own, so that subdomains can be applied concurrently
    mutable Eigen::VectorXd lambda_local, y, x, z, K_plus_scratch, K_ii_scratch;
  };

  const FetiSetup& setup() const { return setup_; }
  const Constraints& constraints() const { return constraints_; }
  const std::vector<Local>& locals() const { return locals_; }
  int n_rows() const { return constraints_.n_rows(); }
  int n_G_rows() const { return static_cast<int>(G_.rows()); }
  const Eigen::SparseMatrix<double, Eigen::RowMajor>& G() const { return G_; }
  // DG, G's rows scaled to unit length (D = diag(1/‖G_i‖)): the coarse solves' form of G.
  const Eigen::SparseMatrix<double, Eigen::RowMajor>& scaled_G() const { return DG_; }

  // y = F x (one application: per subdomain a K⁺ solve, or a dense product with F_s where
  // explicit, spread over setup().threads(); the local results are summed in subdomain order,
  // so y does not depend on the thread count).
  void apply_F(const Eigen::VectorXd& x, Eigen::VectorXd& y) const;
  // y = M⁻¹ x, the scene's preconditioner of F (SolverSettings::preconditioner, not none):
  //   M⁻¹ = Σ_i W⁻¹D_iW⁻¹ B_i T_i B_iᵀ W⁻¹D_iW⁻¹,  T_i = K_i (lumped) or S_i (Dirichlet),
  // B_i the local rows as scaled by the weights W (Constraints::weight), and D_i the stiffness
  // weights of the row's parties, δ_ri = (1/k_ri) / Σ_j (1/k_rj), k_ri the diagonal stiffness
  // of subdomain i under row r (docs/method.md §8). For one row shared by springs of
  // stiffness k_i this makes M⁻¹ = 1/F exactly; the macro subdomain (K = 0) is no party.
  // The caller projects: P M⁻¹ P.
  void apply_preconditioner(const Eigen::VectorXd& x, Eigen::VectorXd& y) const;
  // y = Q x = Gᵀ(GGᵀ)⁻¹G x.
  void apply_Q(const Eigen::VectorXd& x, Eigen::VectorXd& y) const;
  using Profile = OperatorProfile;
  const Profile& profile() const { return profile_; }
  // d = B K⁺ f − t·c (t the load factor of the prescribed displacements, FetiSetup::load_factor).
  Eigen::VectorXd d(const Eigen::VectorXd& f, double t) const;
  // e = R̂ᵀ f, stacked per subdomain.
  Eigen::VectorXd e(const Eigen::VectorXd& f) const;
  // λ₀ = Gᵀ(GGᵀ)⁻¹ e: the least-norm solution of Gλ = e.
  Eigen::VectorXd lambda_0(const Eigen::VectorXd& e) const;
  // (GGᵀ)⁻¹ G r: the coarse solve, e.g. α = (GGᵀ)⁻¹G(Fλ − d − m) from the SMALBE multiplier m.
  Eigen::VectorXd coarse_solve(const Eigen::VectorXd& r) const;
  // F = B K⁺ Bᵀ, dense (n_rows² doubles: for the condensed cell, not for the QP), on every rank:
  // Σ_s of the F_s, each formed by its owner (Local::F where explicit, one K⁺ solve per row
  // where not) and summed in subdomain order.
  Eigen::MatrixXd explicit_F() const;
  // x_i = K_i⁺ (f_i − B_iᵀλ) for every subdomain, into a global vector.
  Eigen::VectorXd K_plus_residual(const Eigen::VectorXd& f, const Eigen::VectorXd& lambda) const;

 private:
  void set_preconditioner_scale();
  // y += Σ_i B_i-rows of z_i over every subdomain of every rank (z_i in Local::z; the macro
  // subdomain's left out when `skip_macro`): each rank sums its owned subdomains in subdomain
  // order into its slots, the slots are gathered, and added in rank order. Ownership is
  // contiguous, so that is subdomain order again, the same bits on every rank.
  void add_row_sums(Eigen::VectorXd& y, bool skip_macro) const;

  // The exchange's layout: rank p's slots are all[displs[p], displs[p] + counts[p]), one per row
  // its subdomains touch (ascending); row[i] is slot i's row. The u of K_plus_residual is
  // gathered the same way by owned DOF ranges (dof_counts, dof_displs).
  struct Exchange {
    std::vector<int> counts, displs, row;
    std::vector<int> dof_counts, dof_displs;
    mutable Eigen::VectorXd all;
  };
  void set_exchange();

  const FetiSetup& setup_;
  Constraints constraints_;
  std::vector<Local> locals_;
  Eigen::SparseMatrix<double, Eigen::RowMajor> G_;
  // The coarse solves work with DG, D = diag(1/‖G_i‖) (rows of unit length). Q, λ₀ and α̂ do not
  // depend on the scaling of G's rows, but the factor of GGᵀ does: an RVE's macro rows (entries of
  // the cell's length on every periodic row) and a small fibre piece's turn differ in length by
  // orders of magnitude, and unscaled the 144-fibre ladder RVE's Q was applied to 4e-11 of ‖x‖
  // with G(I − Q)x at 7e-4, leaving Gλ − e at 5e-5 of its terms while the QP saw Qx ≈ 0.
  Eigen::VectorXd G_row_scale_;
  Eigen::SparseMatrix<double, Eigen::RowMajor> DG_;
  mutable linalg::SparseCholesky GGt_;
  Eigen::SparseMatrix<double> with_joint_null_modes(const Eigen::SparseMatrix<double>& GGt);
  mutable Eigen::VectorXd G_scratch_, G_solution_;
  mutable Profile profile_;
  Exchange exchange_;
};

}  // namespace dualcell::feti
