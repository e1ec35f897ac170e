#pragma once
// SMALBE's operators on the dual problem (docs/method.md §6, §7): A + ρQ with A = PFP, and the
// projected preconditioner P M⁻¹ P + Q/ρ, each applied with the Q x that P x needs, and the norm
// estimate of PFP that every cached problem carries. Shared by the contact solver's QPs and its
// onset problems.
#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "feti/dual.hpp"
#include "linalg/sparse_cholesky.hpp"
#include "qp/face.hpp"

namespace dualcell::feti {

// y = P T P x + s·Q x with P = I − Q and T = F or M⁻¹ (SMALBE's A + ρQ and M⁻¹ + Q/ρ),
// reusing the Q x that P x needs: two applications of Q. Work vectors allocated once per solve.
class ProjectedPlusShiftedQ {
 public:
  using Apply = void (DualProblem::*)(const Eigen::VectorXd&, Eigen::VectorXd&) const;
  ProjectedPlusShiftedQ(const DualProblem& dual, Apply T, int m)
      : dual_(dual), T_(T), Qx_(m), Px_(m), TPx_(m), QTPx_(m) {}
  void operator()(const Eigen::VectorXd& x, double shift, Eigen::VectorXd& y) {
    dual_.apply_Q(x, Qx_);
    Px_ = x - Qx_;
    (dual_.*T_)(Px_, TPx_);
    dual_.apply_Q(TPx_, QTPx_);
    y = TPx_ - QTPx_;
    if (shift != 0) y += shift * Qx_;
  }

 private:
  const DualProblem& dual_;
  Apply T_;
  Eigen::VectorXd Qx_, Px_, TPx_, QTPx_;
};

// SMALBE's face solve on the dual (qp/face.hpp, docs/method.md §7b), with the rows of unit length
// DG: S = (DG)_F (DG)_Fᵀ + δI factorised by CHOLMOD once per face. S is singular where the free
// rows leave a rigid motion unseen (every contact row of a fibre open, a fibre touching at one
// row); δ = 1e-13 of S's largest diagonal entry makes it definite, and on those modes Ĝ_Fᵀ c
// vanishes anyway. A coarse row with no free entry is decoupled (its diagonal set to 1, c = 0).
class FaceCoarse final : public qp::FaceProjector {
 public:
  explicit FaceCoarse(const DualProblem& dual) : DG_(dual.scaled_G()) {}
  bool set_face(const Eigen::VectorXd& free) override;
  void solve_coarse(const Eigen::VectorXd& w, Eigen::VectorXd& c) override;
  void apply_Gt(const Eigen::VectorXd& c, Eigen::VectorXd& v) override;

 private:
  const Eigen::SparseMatrix<double, Eigen::RowMajor>& DG_;
  Eigen::VectorXd Gw_;
  linalg::SparseCholesky S_;
};

// ‖PFP‖ by qp::estimate_norm (20 applications from a fixed start vector): part of building a
// problem, so that it is a function of the problem alone and no QP's count depends on which
// came first.
double estimate_norm_PFP(const DualProblem& dual);

}  // namespace dualcell::feti
