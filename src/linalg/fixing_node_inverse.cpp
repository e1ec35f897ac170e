#include "linalg/fixing_node_inverse.hpp"

#include <algorithm>
#include <string>

namespace dualcell::linalg {

namespace {

[[noreturn]] void setup_error(Eigen::Index n, const std::string& detail) {
  throw CholeskyError(CholeskyStatus::invalid_input, CholeskyPhase::setup, n, detail);
}

// Sorted copy of the fixed DOF list; throws on out-of-range or repeated ones.
std::vector<Eigen::Index> sorted_fixed_dofs(Eigen::Index n, std::span<const Eigen::Index> dofs) {
  std::vector<Eigen::Index> fixed(dofs.begin(), dofs.end());
  std::sort(fixed.begin(), fixed.end());
  for (std::size_t k = 0; k < fixed.size(); ++k) {
    if (fixed[k] < 0 || fixed[k] >= n)
      setup_error(n, "fixed DOF " + std::to_string(fixed[k]) + " out of range [0, " + std::to_string(n) + ")");
    if (k > 0 && fixed[k] == fixed[k - 1]) setup_error(n, "fixed DOF " + std::to_string(fixed[k]) + " listed twice");
  }
  return fixed;
}

}  // namespace

FixingNodeInverse::FixingNodeInverse(const SparseMatrix& K, std::span<const Eigen::Index> fixed_dofs,
                                     const CholmodOptions& options, std::span<const Eigen::Index> last_dofs) {
  const Eigen::Index n = K.rows();
  if (K.rows() != K.cols())
    setup_error(n, "K is not square (" + std::to_string(K.rows()) + "x" + std::to_string(K.cols()) + ")");
  n_ = n;
  fixed_ = sorted_fixed_dofs(n, fixed_dofs);

  // Reduced numbering: new_index[i] = position among free DOFs, or -1.
  std::vector<int> new_index(static_cast<std::size_t>(n), -1);
  std::vector<Eigen::Index> free;
  free.reserve(static_cast<std::size_t>(n) - fixed_.size());
  {
    std::size_t f = 0;
    for (Eigen::Index i = 0; i < n; ++i) {
      if (f < fixed_.size() && fixed_[f] == i) {
        ++f;
        continue;
      }
      new_index[static_cast<std::size_t>(i)] = static_cast<int>(free.size());
      free.push_back(i);
    }
  }
  const auto nr = static_cast<Eigen::Index>(free.size());

  // K_rr, lower triangle only.  The renumbering is monotone, so "lower"
  // in K and in K_rr coincide and row order within a column is kept.
  std::int64_t strictly_lower = 0, strictly_upper = 0, kept = 0;
  for (Eigen::Index j = 0; j < n; ++j)
    for (SparseMatrix::InnerIterator it(K, j); it; ++it) {
      if (it.row() > j)
        ++strictly_lower;
      else if (it.row() < j)
        ++strictly_upper;
      if (it.row() >= j && new_index[it.row()] >= 0 && new_index[j] >= 0) ++kept;
    }
  if (strictly_upper > 0 && strictly_lower == 0)
    setup_error(n,
                "K has only upper-triangular off-diagonal entries; only the lower "
                "triangle is read (pass full or lower storage)");

  SparseMatrix Krr(nr, nr);
  Krr.resizeNonZeros(static_cast<Eigen::Index>(kept));
  int* outer = Krr.outerIndexPtr();
  int* inner = Krr.innerIndexPtr();
  double* val = Krr.valuePtr();
  int pos = 0;
  outer[0] = 0;
  for (Eigen::Index c = 0; c < nr; ++c) {
    const Eigen::Index j = free[static_cast<std::size_t>(c)];
    for (SparseMatrix::InnerIterator it(K, j); it; ++it) {
      const int r = new_index[it.row()];
      if (it.row() >= j && r >= 0) {
        inner[pos] = r;
        val[pos] = it.value();
        ++pos;
      }
    }
    outer[c + 1] = pos;
  }

  // The last DOFs in K_rr's numbering (fixed ones have none).
  last_.assign(last_dofs.begin(), last_dofs.end());
  std::vector<int> last_free;
  {
    std::vector<char> seen(static_cast<std::size_t>(n), 0);
    for (Eigen::Index d : last_) {
      if (d < 0 || d >= n || seen[d]) setup_error(n, "last DOF " + std::to_string(d) + " out of range or repeated");
      seen[d] = 1;
      if (new_index[d] >= 0) last_free.push_back(new_index[d]);
    }
  }
  SparseCholesky chol(options);  // released at the end: L_ is all that is kept
  chol.compute(Krr, last_free);
  SparseCholesky::TriangularFactor factor = chol.triangular_factor();
  L_ = std::move(factor.L);
  gather_.resize(static_cast<std::size_t>(nr));
  for (Eigen::Index k = 0; k < nr; ++k)
    gather_[static_cast<std::size_t>(k)] = free[static_cast<std::size_t>(factor.perm[static_cast<std::size_t>(k)])];
  // The ordering must have put them last (CAMD's constraint): last_block_inverse relies on it.
  const auto nb = static_cast<Eigen::Index>(last_free.size());
  std::vector<char> is_last(static_cast<std::size_t>(n), 0);
  for (Eigen::Index d : last_) is_last[d] = 1;
  for (Eigen::Index k = nr - nb; k < nr; ++k)
    if (!is_last[gather_[static_cast<std::size_t>(k)]])
      throw CholeskyError(CholeskyStatus::invalid_input, CholeskyPhase::analyze, n_,
                          "the constrained ordering did not put the last DOFs last");
}

double FixingNodeInverse::factor_flops() const noexcept {
  double flops = 0;
  for (Eigen::Index j = 0; j < L_.outerSize(); ++j) {
    const double c = L_.outerIndexPtr()[j + 1] - L_.outerIndexPtr()[j];
    flops += c * c;
  }
  return flops;
}

Eigen::MatrixXd FixingNodeInverse::last_block_inverse() const {
  const auto nr = static_cast<Eigen::Index>(gather_.size());
  Eigen::Index nb = 0;
  for (Eigen::Index d : last_) nb += std::binary_search(fixed_.begin(), fixed_.end(), d) ? 0 : 1;
  // L_bb, dense: the trailing nb columns of L, rows from nr − nb on (L is lower: nothing above).
  Eigen::MatrixXd L_bb = Eigen::MatrixXd::Zero(nb, nb);
  for (Eigen::Index j = nr - nb; j < nr; ++j)
    for (SparseMatrix::InnerIterator it(L_, j); it; ++it) L_bb(it.row() - (nr - nb), j - (nr - nb)) = it.value();
  // L_bb⁻¹ by a blocked triangular solve with the identity, then S_bb⁻¹ = L_bb⁻ᵀ L_bb⁻¹ into the
  // lower triangle, mirrored. Eigen's own kernels, not a threaded BLAS (dpotri on OpenBLAS was
  // 3× faster but its bits change with OpenBLAS's thread count, and so would the solution's
  // with the number of ranks sharing a machine).
  Eigen::MatrixXd L_inverse = Eigen::MatrixXd::Identity(nb, nb);
  L_bb.triangularView<Eigen::Lower>().solveInPlace(L_inverse);
  Eigen::MatrixXd S_inverse = Eigen::MatrixXd::Zero(nb, nb);
  S_inverse.selfadjointView<Eigen::Lower>().rankUpdate(L_inverse.transpose());
  S_inverse.triangularView<Eigen::StrictlyUpper>() = S_inverse.transpose();
  // Back to last_'s order: position in the factor of each DOF.
  std::vector<Eigen::Index> position(static_cast<std::size_t>(n_), -1);
  for (Eigen::Index k = nr - nb; k < nr; ++k) position[gather_[static_cast<std::size_t>(k)]] = k - (nr - nb);
  const auto m = static_cast<Eigen::Index>(last_.size());
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(m, m);
  for (Eigen::Index j = 0; j < m; ++j) {
    const Eigen::Index pj = position[last_[j]];
    if (pj < 0) continue;  // fixed
    for (Eigen::Index i = 0; i < m; ++i) {
      const Eigen::Index pi = position[last_[i]];
      if (pi >= 0) out(i, j) = S_inverse(pi, pj);
    }
  }
  return out;
}

void FixingNodeInverse::apply(const Eigen::VectorXd& f, Eigen::VectorXd& x, Eigen::VectorXd& scratch) const {
  const auto nr = static_cast<Eigen::Index>(gather_.size());
  // A moved-from object has lost its vectors but kept n_.
  if (static_cast<Eigen::Index>(gather_.size() + fixed_.size()) != n_ || L_.rows() != nr)
    throw CholeskyError(CholeskyStatus::invalid_input, CholeskyPhase::solve, n_,
                        "FixingNodeInverse has no factorisation (moved from?)");
  if (f.size() != n_ || x.size() != n_ || scratch.size() != nr)
    throw CholeskyError(CholeskyStatus::invalid_input, CholeskyPhase::solve, n_,
                        "FixingNodeInverse::apply: x must have size n() = " + std::to_string(n_) +
                            " and scratch n() minus the fixed DOFs = " + std::to_string(nr));
  for (Eigen::Index k = 0; k < nr; ++k) scratch[k] = f[gather_[static_cast<std::size_t>(k)]];
  L_.triangularView<Eigen::Lower>().solveInPlace(scratch);
  L_.transpose().triangularView<Eigen::Upper>().solveInPlace(scratch);
  for (Eigen::Index i : fixed_) x[i] = 0.0;
  for (Eigen::Index k = 0; k < nr; ++k) x[gather_[static_cast<std::size_t>(k)]] = scratch[k];
}

}  // namespace dualcell::linalg
