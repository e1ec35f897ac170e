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
//   GGᵀ    | GGt_                | small sparse SPD, CHOLMOD, factorised once per problem
//
// No matrix of size dim u or dim λ is ever dense: F and Q are applied as operators.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

#include "feti/constraints.hpp"
#include "feti/setup.hpp"
#include "linalg/sparse_cholesky.hpp"

namespace dualcell::feti {

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
    // Preconditioner row factors δ_ri / w_r² (see apply_preconditioner); empty without one.
    Eigen::VectorXd preconditioner_scale;
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

  // y = F x (one application: a K⁺ solve per subdomain, spread over setup().threads(); the
  // local results are summed in subdomain order, so y does not depend on the thread count).
  void apply_F(const Eigen::VectorXd& x, Eigen::VectorXd& y) const;
  // y = M⁻¹ x, the scene's preconditioner of F (SolverSettings::preconditioner, not none):
  //   M⁻¹ = Σ_i W⁻¹D_iW⁻¹ B_i T_i B_iᵀ W⁻¹D_iW⁻¹,  T_i = K_i (lumped) or S_i (Dirichlet),
  // B_i the local rows as scaled by the weights W (Constraints::weight), and D_i the stiffness
  // weights of the row's parties, δ_ri = (1/k_ri) / Σ_j (1/k_rj), k_ri the diagonal stiffness
  // of subdomain i under row r (Rixen & Farhat 1999). For one row shared by springs of
  // stiffness k_i this makes M⁻¹ = 1/F exactly; the macro subdomain (K = 0) is no party.
  // The caller projects: P M⁻¹ P.
  void apply_preconditioner(const Eigen::VectorXd& x, Eigen::VectorXd& y) const;
  // y = Q x = Gᵀ(GGᵀ)⁻¹G x.
  void apply_Q(const Eigen::VectorXd& x, Eigen::VectorXd& y) const;
  // Wall time spent in apply_F, apply_Q and apply_preconditioner since construction (a
  // profile for the performance report; one clock read per call, nothing per subdomain).
  struct Profile {
    double F = 0, Q = 0, preconditioner = 0;
  };
  const Profile& profile() const { return profile_; }
  // d = B K⁺ f − t·c (t the load factor of the prescribed displacements, FetiSetup::load_factor).
  Eigen::VectorXd d(const Eigen::VectorXd& f, double t) const;
  // e = R̂ᵀ f, stacked per subdomain.
  Eigen::VectorXd e(const Eigen::VectorXd& f) const;
  // λ₀ = Gᵀ(GGᵀ)⁻¹ e: the least-norm solution of Gλ = e.
  Eigen::VectorXd lambda_0(const Eigen::VectorXd& e) const;
  // (GGᵀ)⁻¹ G r: the coarse solve, e.g. α = (GGᵀ)⁻¹G(Fλ − d − m) from the SMALBE multiplier m.
  Eigen::VectorXd coarse_solve(const Eigen::VectorXd& r) const;
  // x_i = K_i⁺ (f_i − B_iᵀλ) for every subdomain, into a global vector.
  Eigen::VectorXd K_plus_residual(const Eigen::VectorXd& f, const Eigen::VectorXd& lambda) const;

 private:
  void set_preconditioner_scale();

  const FetiSetup& setup_;
  Constraints constraints_;
  std::vector<Local> locals_;
  Eigen::SparseMatrix<double, Eigen::RowMajor> G_;
  mutable linalg::SparseCholesky GGt_;
  mutable Eigen::VectorXd G_scratch_, G_solution_;
  mutable Profile profile_;
};

}  // namespace dualcell::feti
