#pragma once
// K⁺ of a floating subdomain by fixing nodes (docs/method.md, "The generalised inverse K⁺"):
// a generalised inverse (K K⁺ K = K) of a symmetric positive SEMI-definite K (n × n) with a
// kernel of dimension m. With f the m fixed DOFs and r the rest, such that K_rr = K(r, r) is
// regular,
//
//     K⁺ = Pᵀ [ K_rr⁻¹  0 ] P,   i.e. x_r = K_rr⁻¹ f_r,  x_f = 0.
//              [ 0       0 ]
//
// This is a generalised inverse exactly when rank(K_rr) = rank(K): exactly dim ker K DOFs are
// fixed and no kernel vector vanishes on them (feti::FetiSetup fixes three DOFs of two
// well-separated nodes of each subdomain). It is symmetric, not the Moore–Penrose inverse; for
// f ⟂ ker K, x = K⁺ f solves K x = f.
//
// K_rr (lower triangle of K, as linalg::SparseCholesky reads it) is factorised once in the
// constructor; the factor is then copied out of CHOLMOD as a plain CSC L and CHOLMOD's copy is
// released, so every apply() is two sparse triangular sweeps (Eigen), gather and scatter fused
// with the fill-reducing permutation: no CHOLMOD call, no BLAS, no allocation, and const, so
// that threads may apply one instance at once, each with its own scratch.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <span>
#include <vector>

#include "linalg/sparse_cholesky.hpp"

namespace dualcell::linalg {

class FixingNodeInverse {
 public:
  using SparseMatrix = SparseCholesky::SparseMatrix;

  // fixed_dofs: distinct indices in [0, n), any order. Throws CholeskyError (setup phase for
  // bad DOF lists; analyze/factorize phases from CHOLMOD, e.g. not_positive_definite when the
  // fixed DOFs leave K_rr indefinite).
  //
  // last_dofs: distinct DOFs (fixed ones allowed) that the factor orders after all others, so
  // that the trailing block L_bb of L is the factor of their Schur complement S_bb and
  // K⁺(b, b) = S_bb⁻¹ = L_bb⁻ᵀ L_bb⁻¹ (last_block_inverse). Empty: the options' ordering.
  FixingNodeInverse(const SparseMatrix& K, std::span<const Eigen::Index> fixed_dofs, const CholmodOptions& options = {},
                    std::span<const Eigen::Index> last_dofs = {});

  // x = K⁺ f (zeros at the fixed DOFs). x must have size n(), scratch n() − fixed DOFs; f and x
  // may be the same object.
  void apply(const Eigen::VectorXd& f, Eigen::VectorXd& x, Eigen::VectorXd& scratch) const;

  // K⁺(b, b), dense and symmetric, b the constructor's last_dofs in their given order (zero rows
  // and columns at fixed DOFs): one dense triangular inverse of L_bb, no solve with all of L.
  Eigen::MatrixXd last_block_inverse() const;
  // Nonzeros of L (the work of one sweep), and Σ_j nnz(L(:, j))², the multiply-adds of the
  // factorisation that made it (the work of making it again).
  Eigen::Index factor_nonzeros() const noexcept { return L_.nonZeros(); }
  double factor_flops() const noexcept;

  Eigen::Index n() const noexcept { return n_; }
  // Size of the scratch apply() needs: n() minus the fixed DOFs.
  Eigen::Index scratch_size() const noexcept { return static_cast<Eigen::Index>(gather_.size()); }
  // Bytes held: the factor L (values, row indices, column starts) and the permutation.
  std::size_t bytes() const noexcept {
    return static_cast<std::size_t>(L_.nonZeros()) * (sizeof(double) + sizeof(SparseMatrix::StorageIndex)) +
           static_cast<std::size_t>(L_.outerSize() + 1) * sizeof(SparseMatrix::StorageIndex) +
           (gather_.size() + fixed_.size() + last_.size()) * sizeof(Eigen::Index);
  }

 private:
  Eigen::Index n_ = 0;
  std::vector<Eigen::Index> fixed_;  // sorted
  std::vector<Eigen::Index> last_;   // as given
  // K_rr = Pᵀ L Lᵀ P as a plain CSC factor; gather_[k] = the DOF of K at position k of P K_rr Pᵀ.
  SparseMatrix L_;
  std::vector<Eigen::Index> gather_;
};

}  // namespace dualcell::linalg
