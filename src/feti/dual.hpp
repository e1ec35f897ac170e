#pragma once
// The dual problem of Total FETI (METHOD §5, thesis §4.1 and §4.6), for one set of
// constraints (one bond state):
//
//   F = B K⁺ Bᵀ,  d = B K⁺ f − c,  G = R̂ᵀ Bᵀ,  e = R̂ᵀ f
//   min ½ λᵀFλ − λᵀd   s.t.  Gλ = e,  ℓ ≤ λ ≤ υ
//
// made homogeneous by λ = λ₀ + μ with λ₀ = Gᵀ(GGᵀ)⁻¹e (bounds shifted by −λ₀), and solved
// with the orthogonal projector P = I − Q, Q = Gᵀ(GGᵀ)⁻¹G, as min ½μᵀPFPμ − μᵀP(d − Fλ₀)
// s.t. Qμ = 0 (SMALBE) and the shifted bounds (MPRGP inside).
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
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "feti/constraints.hpp"
#include "feti/setup.hpp"
#include "linalg/cholmod.hpp"

namespace dualcell::feti {

class DualProblem {
 public:
  DualProblem(const FetiSetup& setup, Constraints constraints);
  DualProblem(const DualProblem&) = delete;
  DualProblem& operator=(const DualProblem&) = delete;

  struct Local {
    std::vector<int> rows;                               // global row indices, ascending
    Eigen::SparseMatrix<double, Eigen::RowMajor> B;      // rows.size() × n_dofs
    Eigen::MatrixXd R_hat;                               // n_dofs × r_i
    Eigen::MatrixXd V;                                   // 3 × r_i: R_hat = R V
    int G_offset = 0;                                    // first row of G for this subdomain
    // scratch for operator applications (no allocation per application); each subdomain's
    // own, so that subdomains can be applied concurrently
    mutable Eigen::VectorXd lambda_local, y, x, z, K_plus_scratch;
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
  // y = Q x = Gᵀ(GGᵀ)⁻¹G x.
  void apply_Q(const Eigen::VectorXd& x, Eigen::VectorXd& y) const;
  // d = B K⁺ f − c.
  Eigen::VectorXd d(const Eigen::VectorXd& f) const;
  // e = R̂ᵀ f, stacked per subdomain.
  Eigen::VectorXd e(const Eigen::VectorXd& f) const;
  // λ₀ = Gᵀ(GGᵀ)⁻¹ e: the least-norm solution of Gλ = e.
  Eigen::VectorXd lambda_0(const Eigen::VectorXd& e) const;
  // (GGᵀ)⁻¹ G r: the coarse solve, e.g. α = (GGᵀ)⁻¹G(Fλ − d − m) from the SMALBE multiplier m.
  Eigen::VectorXd coarse_solve(const Eigen::VectorXd& r) const;
  // x_i = K_i⁺ (f_i − B_iᵀλ) for every subdomain, into a global vector.
  Eigen::VectorXd K_plus_residual(const Eigen::VectorXd& f, const Eigen::VectorXd& lambda) const;

 private:
  const FetiSetup& setup_;
  Constraints constraints_;
  std::vector<Local> locals_;
  Eigen::SparseMatrix<double, Eigen::RowMajor> G_;
  mutable linalg::SparseCholesky GGt_;
  mutable Eigen::VectorXd G_scratch_, G_solution_;
};

}  // namespace dualcell::feti
