// dualcell::linalg -- sparse Cholesky (SuiteSparse CHOLMOD) and the FETI
// "fixing nodes" generalized inverse.
//
// Design (after the idea of Ceres Solver's SparseCholesky, not its code):
//   * CholmodCommon  : RAII owner of a cholmod_common with our option policy
//                      and an error handler that records instead of printing.
//   * SparseCholesky : analyze once (symbolic + fill-reducing ordering),
//                      factorize many times with the same pattern, solve many
//                      times with a factor that is kept.
//   * Every CHOLMOD status becomes a CholeskyStatus; hard failures are
//                      thrown as CholeskyError (phase, size, failing column).
//   * FixedDofPseudoInverse : K^+ of a singular SPSD K with known kernel, by
//                      deleting "fixed" DOFs and factorizing the rest once.
//
// CHOLMOD types are only forward-declared here; <cholmod.h> is needed only by
// src/linalg/cholmod.cpp.  The int-index API (cholmod_*, not cholmod_l_*) is
// used, matching Eigen's default StorageIndex = int, so the input matrix is
// passed to CHOLMOD as a zero-copy view.
//
// Thread safety: none of these classes is thread-safe.  Use one instance per
// thread (in FETI: one per subdomain, owned by the thread that works on it).
// Distinct instances may be used concurrently (the error recorder is
// thread_local; CHOLMOD keeps no global mutable state besides
// SuiteSparse_config, which we never modify).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

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
    CholeskyError(CholeskyStatus status, CholeskyPhase phase, Eigen::Index n,
                  const std::string& detail, Eigen::Index column = -1,
                  Eigen::Index original_column = -1);

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
    const CholmodOptions& options() const noexcept { return options_; }

    // Call protocol: begin_call() resets Common->status and the recorded
    // message; end_call() reads Common->status, copies any message recorded
    // by the error handler (allocates only when there is one) and returns the
    // raw CHOLMOD status.
    void begin_call() noexcept;
    int end_call();

    int raw_status() const noexcept;         // Common->status
    CholeskyStatus status() const noexcept;  // mapped raw_status()
    const std::string& last_message() const noexcept { return message_; }

    // CHOLMOD's own accounting for everything allocated through this common
    // (factor, workspaces, temporaries): current and peak bytes.
    std::size_t memory_in_use() const noexcept;
    std::size_t peak_memory() const noexcept;

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
// object: the first solve with a given number of right-hand sides allocates
// them, later solves with the same count allocate nothing inside CHOLMOD
// (for simplicial factors thanks to a small workaround of a CHOLMOD 5.x
// workspace-reshaping quirk, see solve_impl()).
// Single-vector and block solves keep separate workspaces, so alternating
// between them does not reallocate.  The result is copied (O(n k)) from
// CHOLMOD's X into x/X, which is resized only if its size differs.  b and x
// may be the same object.
class SparseCholesky {
public:
    using SparseMatrix = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

    explicit SparseCholesky(const CholmodOptions& options = {});
    ~SparseCholesky();
    SparseCholesky(SparseCholesky&& other) noexcept;
    SparseCholesky& operator=(SparseCholesky&& other) noexcept;
    SparseCholesky(const SparseCholesky&) = delete;
    SparseCholesky& operator=(const SparseCholesky&) = delete;

    // Symbolic analysis (fill-reducing ordering, supernodes).  Only the
    // pattern of `pattern` is used.  Discards any previous factor (after the
    // argument checks have passed).
    void analyze(const SparseMatrix& pattern);

    // Numeric factorization; requires analyze().  Returns ok or
    // numerical_warning, throws CholeskyError otherwise.
    CholeskyStatus factorize(const SparseMatrix& matrix);

    // analyze(matrix) followed by factorize(matrix).
    CholeskyStatus compute(const SparseMatrix& matrix);

    // x = A^{-1} b.  Requires a successful factorize(); b.size() == n().
    void solve(const Eigen::VectorXd& b, Eigen::VectorXd& x);
    // X = A^{-1} B, column by column in one CHOLMOD call; B.rows() == n().
    void solve(const Eigen::MatrixXd& B, Eigen::MatrixXd& X);

    // The factor as a plain lower-triangular CSC matrix: P A Pᵀ = L Lᵀ, perm[k] = the row of A
    // at position k of P A Pᵀ. A supernodal or LDLᵀ factor is converted on a copy (the kept
    // factor is unchanged). Meant for callers that solve many small systems themselves: a
    // solve is then two sparse triangular sweeps with no CHOLMOD call, no allocation and no
    // shared state (see FixedDofPseudoInverse). Requires a successful factorize().
    struct TriangularFactor {
        SparseMatrix L;
        std::vector<int> perm;
    };
    TriangularFactor triangular_factor();

    // Order of the analyzed matrix (0 before analyze()).
    Eigen::Index n() const noexcept { return n_; }
    bool is_analyzed() const noexcept { return analyzed_; }
    bool is_factorized() const noexcept { return factorized_; }
    bool is_supernodal() const noexcept;

    // Entries of L as CHOLMOD stores them, known right after analyze():
    // supernodal -- the lower-trapezoidal part of every supernode, including
    // explicit zeros from relaxed amalgamation; simplicial -- the column
    // counts (numeric: the nz of each column).  0 before analyze().
    std::int64_t nnz_factor() const noexcept;

    // Bytes held by the factor object: values (8 B), integer arrays (4 B:
    // Perm, ColCount, IPerm; super/pi/px/s or p/i/nz/next/prev) and the
    // struct itself.  After analyze() only, it is the projection for the
    // numeric factor (supernodal: exact from xsize; simplicial: from column
    // counts).  Excludes CHOLMOD workspaces and solve workspaces; see
    // common().peak_memory() for the peak of everything.
    std::size_t bytes() const noexcept;

    // CHOLMOD's rough reciprocal condition estimate (min diag L/max diag L)^2,
    // computed by factorize().  Requires is_factorized(); 1 for n == 0.
    double rcond() const;

    // Outcome of the most recent analyze()/factorize() (also set when they
    // throw).  solve() only throws and leaves it unchanged, so after a
    // successful factorize() it is the quality flag of the current factor:
    // ok or numerical_warning.
    CholeskyStatus last_status() const noexcept { return last_status_; }
    const std::string& last_message() const noexcept { return last_message_; }

    const CholmodOptions& options() const noexcept { return options_; }
    const CholmodCommon& common() const noexcept { return common_; }

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
    void solve_impl(const double* b, Eigen::Index ncols, Workspace& ws, double* x);

    CholmodOptions options_;
    CholmodCommon common_;
    cholmod_factor_struct* factor_ = nullptr;
    Workspace ws_vec_;    // k == 1
    Workspace ws_block_;  // k  > 1 (reallocated when k changes)

    Eigen::Index n_ = 0;
    bool analyzed_ = false;
    bool factorized_ = false;
    double rcond_ = 1.0;

    // Analyzed lower pattern (CSC, row >= col) and O(n) marker for the
    // subset check in factorize().
    std::vector<int> pattern_ptr_;
    std::vector<int> pattern_idx_;
    std::vector<int> marker_;

    CholeskyStatus last_status_ = CholeskyStatus::ok;
    std::string last_message_;
};

// --------------------------------------------------------------------------
// FixedDofPseudoInverse
// --------------------------------------------------------------------------

// Optional verification, in FixedDofPseudoInverse, of the fixing against a
// known kernel basis R (n x m).  Q denotes an orthonormal basis of range(R).
struct KernelCheck {
    // ||K Q||_F <= residual_tol * ||K||_F required.
    double residual_tol = 1e-8;
    // sigma_min(Q(fixed, :)) >= min_fixed_singular required (a value in
    // [0, 1]; small means some kernel vector nearly vanishes on the fixed
    // DOFs, so K_rr is nearly singular).
    double min_fixed_singular = 1e-6;
};

// Generalized inverse of a symmetric positive SEMI-definite K (n x n) with a
// kernel of dimension m, by the FETI "fixing nodes" technique: with r the
// free DOFs and f the m fixed DOFs such that K_rr = K(r, r) is regular,
//
//     K^+ = P^T [ K_rr^{-1}  0 ] P ,   i.e. x_r = K_rr^{-1} f_r,  x_f = 0.
//               [ 0          0 ]
//
// This satisfies K K^+ K = K exactly when rank(K_rr) = rank(K), i.e. when
// exactly dim ker K DOFs are fixed and no kernel vector vanishes on them
// (R(fixed, :) nonsingular for a kernel basis R).  It is symmetric but not
// the Moore-Penrose inverse.  For f in range(K) (f orthogonal to ker K),
// x = K^+ f solves K x = f.
//
// K: same storage rules as SparseCholesky (lower triangle read).  The
// reduced matrix K_rr (lower part only) is assembled and factorized once in
// the constructor; K itself is not kept.  Constructor failures throw
// CholeskyError (setup phase for bad DOF lists / kernel; analyze/factorize
// phases from CHOLMOD, e.g. not_positive_definite when the fixed DOFs do not
// remove the kernel).
//
// Caveat: a fixing that misses a kernel vector makes K_rr singular, but in
// floating point its last pivot is usually a rounding-level positive number,
// so CHOLMOD need not fail: expect numerical_warning from status() (rcond
// check) rather than an exception.  The kernel-checking constructor detects
// such fixings (and too many fixed DOFs, which gives a regular K_rr but no
// generalized inverse) reliably, before factorizing.
//
// After factorising, the factor is copied out of CHOLMOD as a plain CSC L
// (SparseCholesky::triangular_factor) and CHOLMOD's own copy is released: every
// apply() is two sparse triangular sweeps (Eigen) with gather and scatter fused
// with the fill-reducing permutation, and nothing of CHOLMOD is kept.
// apply() does not allocate once x (resp. X) has the right size (and, for the
// block version, after the first call with a given column count).  The two
// apply() overloads without a scratch argument use scratch kept in the object
// and must not be called on one instance from two threads at once; the const
// overload with caller-owned scratch may.  f and x may be the same object.
class FixedDofPseudoInverse {
public:
    using SparseMatrix = SparseCholesky::SparseMatrix;

    // fixed_dofs: distinct indices in [0, n), any order (stored sorted).
    FixedDofPseudoInverse(const SparseMatrix& K, std::span<const Eigen::Index> fixed_dofs,
                          const CholmodOptions& options = {});

    // Same, but first verifies that `kernel` (n x m, columns spanning ker K)
    // has m == fixed_dofs.size() independent columns, lies in ker K and is
    // "seen" by the fixed DOFs (see KernelCheck); throws invalid_input
    // (setup phase) otherwise.
    FixedDofPseudoInverse(const SparseMatrix& K, std::span<const Eigen::Index> fixed_dofs,
                          const Eigen::MatrixXd& kernel, const KernelCheck& check = {},
                          const CholmodOptions& options = {});

    FixedDofPseudoInverse(FixedDofPseudoInverse&&) noexcept = default;
    FixedDofPseudoInverse& operator=(FixedDofPseudoInverse&&) noexcept = default;
    FixedDofPseudoInverse(const FixedDofPseudoInverse&) = delete;
    FixedDofPseudoInverse& operator=(const FixedDofPseudoInverse&) = delete;
    ~FixedDofPseudoInverse() = default;

    // x = K^+ f (zeros at fixed DOFs).  f.size() == n().
    void apply(const Eigen::VectorXd& f, Eigen::VectorXd& x);
    // The same with caller-owned scratch of size n() - fixed_dofs().size(): const, so distinct
    // threads may apply one instance concurrently, each with its own scratch. Two sparse
    // triangular sweeps with L (Eigen), gather and scatter fused with the fill-reducing
    // permutation; no CHOLMOD call, no allocation (x must already have size n()).
    void apply(const Eigen::VectorXd& f, Eigen::VectorXd& x, Eigen::VectorXd& scratch) const;
    // X = K^+ F, column-wise.  F.rows() == n().
    void apply(const Eigen::MatrixXd& F, Eigen::MatrixXd& X);

    Eigen::Index n() const noexcept { return n_; }
    const std::vector<Eigen::Index>& fixed_dofs() const noexcept { return fixed_; }
    const std::vector<Eigen::Index>& free_dofs() const noexcept { return free_; }
    // Entries of the Cholesky factor of K_rr as kept (order n() - fixed_dofs().size()).
    Eigen::Index nnz_factor() const noexcept { return L_.nonZeros(); }
    // Status of the factorization of K_rr (ok or numerical_warning).
    CholeskyStatus status() const noexcept { return status_; }

private:
    void build(const SparseMatrix& K, std::span<const Eigen::Index> fixed_dofs);
    void require_factor(Eigen::Index rows) const;

    Eigen::Index n_ = 0;
    std::vector<Eigen::Index> fixed_;
    std::vector<Eigen::Index> free_;
    CholmodOptions options_;
    CholeskyStatus status_ = CholeskyStatus::ok;
    // K_rr = Pᵀ L Lᵀ P as a plain CSC factor; gather_[k] = the DOF of K at position k of P K_rr Pᵀ.
    SparseMatrix L_;
    std::vector<Eigen::Index> gather_;
    Eigen::VectorXd fr_;       // gathered rhs, solved in place
    Eigen::MatrixXd Fr_;       // block version
};

}  // namespace dualcell::linalg
