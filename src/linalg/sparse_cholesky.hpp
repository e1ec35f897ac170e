// dualcell::linalg -- sparse Cholesky through SuiteSparse CHOLMOD.
//
// Design (after the idea of Ceres Solver's SparseCholesky, not its code):
//   * CholmodCommon  : RAII owner of a cholmod_common with our option policy
//                      and an error handler that records instead of printing.
//   * SparseCholesky : analyze once (symbolic + fill-reducing ordering),
//                      factorize many times with the same pattern, solve many
//                      times with a factor that is kept.
//   * Every CHOLMOD status becomes a CholeskyStatus; hard failures are
//                      thrown as CholeskyError (phase, size, failing column).
// The fixing-node generalised inverse K⁺ built on it: linalg/fixing_node_inverse.hpp.
//
// CHOLMOD types are only forward-declared here; <cholmod.h> is needed only by
// src/linalg/sparse_cholesky.cpp.  The int-index API (cholmod_*, not cholmod_l_*) is
// used, matching Eigen's default StorageIndex = int, so the input matrix is
// passed to CHOLMOD as a zero-copy view.
//
// Thread safety: none of these classes is thread-safe.  Use one instance per
// thread.  Distinct instances may be used concurrently (the error recorder is
// thread_local; CHOLMOD keeps no global mutable state besides
// SuiteSparse_config, which we never modify).
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

// CHOLMOD's struct tags (cholmod_core.h: typedef struct cholmod_X_struct {...}
// cholmod_X;).  Forward-declared to keep <cholmod.h> out of this header.
struct cholmod_common_struct;
struct cholmod_factor_struct;
struct cholmod_dense_struct;

namespace dualcell::linalg {

// --------------------------------------------------------------------------
// Status and errors
// --------------------------------------------------------------------------

// Outcome of a CHOLMOD call (or of the wrapper's own argument checks).
enum class CholeskyStatus {
  ok,                     // CHOLMOD_OK
  not_positive_definite,  // CHOLMOD_NOT_POSDEF (warning in CHOLMOD, an error here)
  out_of_memory,          // CHOLMOD_OUT_OF_MEMORY
  too_large,              // CHOLMOD_TOO_LARGE (integer overflow in sizes)
  invalid_input,          // CHOLMOD_INVALID, CHOLMOD_NOT_INSTALLED, and the wrapper's checks
  numerical_warning,      // CHOLMOD_DSMALL, other positive codes, rcond below threshold
  internal_error,         // CHOLMOD_GPU_PROBLEM, unknown negative codes, inconsistent state
};

// Stable lowercase name, e.g. "not_positive_definite".
std::string_view to_string(CholeskyStatus status) noexcept;

// Explicit mapping of a raw CHOLMOD status code (Common->status):
//   0 -> ok;  1 (NOT_POSDEF) -> not_positive_definite;  2 (DSMALL) and any
//   other positive code -> numerical_warning;  -1 (NOT_INSTALLED) and
//   -4 (INVALID) -> invalid_input;  -2 -> out_of_memory;  -3 -> too_large;
//   -5 (GPU_PROBLEM) and any other negative code -> internal_error.
CholeskyStatus status_from_cholmod(int cholmod_status) noexcept;

// Phase of the computation in which something went wrong.
//   setup: argument checks of a composite object (FixedDofPseudoInverse)
//          before any CHOLMOD phase is entered.
enum class CholeskyPhase { setup, analyze, factorize, solve };

std::string_view to_string(CholeskyPhase phase) noexcept;

// Thrown on every hard failure.  what() reads, e.g.:
//   "dualcell::linalg Cholesky factorize failed (n=2500):
//    not_positive_definite: leading minor of order 1234 is not positive
//    (failing column 1233 of the permuted matrix = column 57 of the input);
//    CHOLMOD: not positive definite"
class CholeskyError : public std::runtime_error {
 public:
  CholeskyError(CholeskyStatus status, CholeskyPhase phase, Eigen::Index n, const std::string& detail,
                Eigen::Index column = -1, Eigen::Index original_column = -1);

  CholeskyStatus status() const noexcept { return status_; }
  CholeskyPhase phase() const noexcept { return phase_; }
  // Order of the matrix involved (-1 if not applicable).
  Eigen::Index matrix_size() const noexcept { return n_; }
  // not_positive_definite only (else -1): L->minor, the column of the
  // *permuted* matrix P A P^T at which the factorization stopped.
  Eigen::Index column() const noexcept { return column_; }
  // not_positive_definite only (else -1): the same column in the numbering
  // of the matrix passed to factorize() (= Perm[L->minor]).
  Eigen::Index original_column() const noexcept { return original_column_; }

 private:
  CholeskyStatus status_;
  CholeskyPhase phase_;
  Eigen::Index n_;
  Eigen::Index column_;
  Eigen::Index original_column_;
};

// --------------------------------------------------------------------------
// Options and the CHOLMOD "common" object
// --------------------------------------------------------------------------

enum class FactorKind {
  supernodal,  // CHOLMOD_SUPERNODAL: BLAS-3 supernodal LL^T (default)
  simplicial,  // CHOLMOD_SIMPLICIAL: up-looking LL^T (final_ll = TRUE, so
               // that indefiniteness is detected as in the supernodal case)
  automatic,   // CHOLMOD_AUTO: CHOLMOD decides from flops/nnz(L)
};

enum class Ordering {
  automatic,  // nmethods = 0: AMD, and METIS too if AMD's fill is poor and
              // CHOLMOD was built with METIS (Debian's is); best is kept
  amd,        // AMD only
  metis,      // METIS only (fails with invalid_input if not installed)
  natural,    // no permutation
};

struct CholmodOptions {
  FactorKind factor_kind = FactorKind::supernodal;
  Ordering ordering = Ordering::automatic;
  // After a successful factorize(), if CHOLMOD's cheap estimate
  // rcond = (min diag L / max diag L)^2 is below this, last_status() is
  // numerical_warning (nothing is thrown).  <= 0 disables the check.
  // Since diag(L)_k^2 is a Schur-complement pivot, lambda_min(A) <=
  // diag(L)_k^2 <= A_kk <= lambda_max(A), so rcond >= 1/kappa_2(A): a
  // warning certifies kappa_2(A) > 1/threshold (up to rounding); no warning
  // certifies nothing (the estimate can be very optimistic).  The default
  // 1e-14 flags matrices that are singular up to rounding: e.g. a K_rr
  // whose fixed DOFs miss a kernel vector gave rcond ~ 1e-15 in the tests.
  double rcond_warning_threshold = 1e-14;
};

// RAII over cholmod_common: cholmod_start() in the constructor,
// cholmod_finish() in the destructor.
//
// The cholmod_common (several KB) is held by unique_ptr, so its address never
// changes; the object is movable (cheap, noexcept) and not copyable.  A
// moved-from CholmodCommon holds nothing (valid() == false, get() == nullptr)
// and may only be destroyed or assigned to.
//
// Settings applied: print = 0 (CHOLMOD prints nothing), error_handler records
// (status, file, line, message) into a thread_local buffer which call sites
// harvest with begin_call()/end_call(); supernodal/ordering per options;
// final_ll = TRUE; quick_return_if_not_posdef = TRUE.
class CholmodCommon {
 public:
  explicit CholmodCommon(const CholmodOptions& options = {});
  ~CholmodCommon();
  CholmodCommon(CholmodCommon&& other) noexcept;
  CholmodCommon& operator=(CholmodCommon&& other) noexcept;
  CholmodCommon(const CholmodCommon&) = delete;
  CholmodCommon& operator=(const CholmodCommon&) = delete;

  bool valid() const noexcept { return common_ != nullptr; }
  cholmod_common_struct* get() noexcept { return common_.get(); }
  const cholmod_common_struct* get() const noexcept { return common_.get(); }

  // Call protocol: begin_call() resets Common->status and the recorded
  // message; end_call() reads Common->status, copies any message recorded
  // by the error handler (allocates only when there is one) and returns the
  // raw CHOLMOD status.
  void begin_call() noexcept;
  int end_call();

  int raw_status() const noexcept;         // Common->status
  CholeskyStatus status() const noexcept;  // mapped raw_status()
  const std::string& last_message() const noexcept { return message_; }

 private:
  struct Deleter {
    void operator()(cholmod_common_struct* c) const noexcept;
  };
  std::unique_ptr<cholmod_common_struct, Deleter> common_;
  CholmodOptions options_;
  std::string message_;
};

// --------------------------------------------------------------------------
// SparseCholesky
// --------------------------------------------------------------------------

// Cholesky factorization P A P^T = L L^T of a sparse symmetric positive
// definite matrix, for repeated solves.
//
// Accepted input: Eigen::SparseMatrix<double, ColMajor, int>, square, either
// compressed or not.  Only the LOWER triangle (row >= col, diagonal included)
// is read (CHOLMOD stype = -1): full symmetric storage and lower-triangular
// storage are both fine; entries above the diagonal are ignored, symmetry is
// NOT checked.  Upper-only storage is rejected (invalid_input) when it is
// detectable, i.e. the matrix has strictly-upper but no strictly-lower
// entries.
//
// Pattern rule: factorize() requires the lower pattern of its argument to be
// a subset of the lower pattern given to analyze() (CHOLMOD's supernodal
// factorization requires this; violating it is undefined behaviour inside
// CHOLMOD).  The wrapper keeps a copy of the analyzed lower pattern and
// checks this in O(nnz) before calling CHOLMOD.
//
// Failure policy:
//   * analyze/factorize/solve throw CholeskyError on every error, including
//     not_positive_definite (with L->minor and the original column).  After a
//     failed factorize() the symbolic analysis is kept: factorize() may be
//     called again with another matrix of the same pattern; solve() throws
//     until a factorize() succeeds.
//   * Argument errors found by the wrapper itself (invalid_input: sizes,
//     pattern, storage, call order) are thrown before anything is changed;
//     only last_status()/last_message() are updated, and an existing factor
//     stays usable.
//   * Warnings do not throw.  factorize() returns ok or numerical_warning
//     (CHOLMOD_DSMALL -- cannot occur with our settings since Common->dbound
//     stays 0 -- or rcond below options.rcond_warning_threshold); the value is
//     also available as last_status(), the text as last_message().
//
// Allocation: analyze() and factorize() allocate (symbolic/numeric factor on
// the first factorize; CHOLMOD also makes one or two temporary permuted copies
// of A inside every factorize -- it cannot be avoided through its API).
// solve() goes through cholmod_solve2 with X/Y/E workspaces kept in the
// object: the first solve allocates them, later solves allocate nothing
// inside CHOLMOD (for simplicial factors thanks to a small workaround of a
// CHOLMOD 5.x workspace-reshaping quirk, see solve_impl()).  The result is
// copied (O(n)) from CHOLMOD's X into x, which is resized only if its size
// differs.  b and x may be the same object.
class SparseCholesky {
 public:
  using SparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

  explicit SparseCholesky(const CholmodOptions& options = {});
  ~SparseCholesky();
  SparseCholesky(SparseCholesky&& other) noexcept;
  SparseCholesky& operator=(SparseCholesky&& other) noexcept;
  SparseCholesky(const SparseCholesky&) = delete;
  SparseCholesky& operator=(const SparseCholesky&) = delete;

  // analyze() once and factorize() per matrix of the same pattern is for Newton-like loops
  // (a fixed pattern, new values); compute() does both for a one-off matrix.
  // Symbolic analysis (fill-reducing ordering, supernodes).  Only the
  // pattern of `pattern` is used.  Discards any previous factor (after the
  // argument checks have passed).
  // last: columns to order after all others (CAMD within each part, no postorder), so that
  // the trailing block of L is the factor of their Schur complement; empty: the options' ordering.
  void analyze(const SparseMatrix& pattern, std::span<const int> last = {});

  // Numeric factorization; requires analyze().  Returns ok or
  // numerical_warning, throws CholeskyError otherwise.
  CholeskyStatus factorize(const SparseMatrix& matrix);

  // analyze(matrix) followed by factorize(matrix).
  CholeskyStatus compute(const SparseMatrix& matrix, std::span<const int> last = {});

  // x = A^{-1} b.  Requires a successful factorize(); b.size() == n().
  void solve(const Eigen::VectorXd& b, Eigen::VectorXd& x);

  // The factor as a plain lower-triangular CSC matrix: P A Pᵀ = L Lᵀ, perm[k] = the row of A
  // at position k of P A Pᵀ. A supernodal or LDLᵀ factor is converted on a copy (the kept
  // factor is unchanged). Meant for callers that solve many small systems themselves: a
  // solve is then two sparse triangular sweeps with no CHOLMOD call, no allocation and no
  // shared state (see FixingNodeInverse). Requires a successful factorize().
  struct TriangularFactor {
    SparseMatrix L;
    std::vector<int> perm;
  };
  TriangularFactor triangular_factor();

  // Order of the analyzed matrix (0 before analyze()).
  Eigen::Index n() const noexcept { return n_; }
  bool is_analyzed() const noexcept { return analyzed_; }
  bool is_factorized() const noexcept { return factorized_; }

  // Outcome of the most recent analyze()/factorize() (also set when they
  // throw).  solve() only throws and leaves it unchanged, so after a
  // successful factorize() it is the quality flag of the current factor:
  // ok or numerical_warning.
  CholeskyStatus last_status() const noexcept { return last_status_; }
  const std::string& last_message() const noexcept { return last_message_; }

 private:
  struct Workspace {
    cholmod_dense_struct* X = nullptr;
    cholmod_dense_struct* Y = nullptr;
    cholmod_dense_struct* E = nullptr;
  };

  void require_common(CholeskyPhase phase) const;
  void require_factorized(CholeskyPhase phase) const;
  void check_lower_storage(const SparseMatrix& A, CholeskyPhase phase) const;
  void check_pattern_subset(const SparseMatrix& A);
  void release() noexcept;  // frees factor and workspaces
  void free_workspace(Workspace& ws) noexcept;
  [[noreturn]] void throw_cholmod(CholeskyPhase phase, int raw, const char* what);
  void solve_impl(const double* b, double* x);

  CholmodOptions options_;
  CholmodCommon common_;
  cholmod_factor_struct* factor_ = nullptr;
  Workspace ws_;

  Eigen::Index n_ = 0;
  bool analyzed_ = false;
  bool factorized_ = false;

  // Analyzed lower pattern (CSC, row >= col) and O(n) marker for the
  // subset check in factorize().
  std::vector<int> pattern_ptr_;
  std::vector<int> pattern_idx_;
  std::vector<int> marker_;

  CholeskyStatus last_status_ = CholeskyStatus::ok;
  std::string last_message_;
};

}  // namespace dualcell::linalg
