#include "linalg/sparse_cholesky.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <sstream>
#include <utility>

// Debian/Ubuntu install CHOLMOD under /usr/include/suitesparse and ship no
// pkg-config file for it, so the build may or may not add that directory to
// the include path.  <suitesparse/cholmod.h> works from /usr/include (its own
// #include "..." lines resolve relative to its directory).
#if __has_include(<cholmod.h>)
#include <cholmod.h>
#elif __has_include(<suitesparse/cholmod.h>)
#include <suitesparse/cholmod.h>
#else
#error "CHOLMOD header <cholmod.h> not found"
#endif

namespace dualcell::linalg {

// ==========================================================================
// Status mapping
// ==========================================================================

std::string_view to_string(CholeskyStatus status) noexcept {
  switch (status) {
    case CholeskyStatus::ok:
      return "ok";
    case CholeskyStatus::not_positive_definite:
      return "not_positive_definite";
    case CholeskyStatus::out_of_memory:
      return "out_of_memory";
    case CholeskyStatus::too_large:
      return "too_large";
    case CholeskyStatus::invalid_input:
      return "invalid_input";
    case CholeskyStatus::numerical_warning:
      return "numerical_warning";
    case CholeskyStatus::internal_error:
      return "internal_error";
  }
  return "unknown_status";
}

std::string_view to_string(CholeskyPhase phase) noexcept {
  switch (phase) {
    case CholeskyPhase::setup:
      return "setup";
    case CholeskyPhase::analyze:
      return "analyze";
    case CholeskyPhase::factorize:
      return "factorize";
    case CholeskyPhase::solve:
      return "solve";
  }
  return "unknown_phase";
}

CholeskyStatus status_from_cholmod(int s) noexcept {
  switch (s) {
    case CHOLMOD_OK:
      return CholeskyStatus::ok;
    case CHOLMOD_NOT_POSDEF:
      return CholeskyStatus::not_positive_definite;
    case CHOLMOD_DSMALL:
      return CholeskyStatus::numerical_warning;
    case CHOLMOD_NOT_INSTALLED:
      return CholeskyStatus::invalid_input;
    case CHOLMOD_OUT_OF_MEMORY:
      return CholeskyStatus::out_of_memory;
    case CHOLMOD_TOO_LARGE:
      return CholeskyStatus::too_large;
    case CHOLMOD_INVALID:
      return CholeskyStatus::invalid_input;
    case CHOLMOD_GPU_PROBLEM:
      return CholeskyStatus::internal_error;
    default:
      // Codes unknown to this CHOLMOD version: positive ones are
      // warnings by CHOLMOD's convention, negative ones failures.
      return s > 0 ? CholeskyStatus::numerical_warning : CholeskyStatus::internal_error;
  }
}

namespace {

std::string make_what(CholeskyStatus status, CholeskyPhase phase, Eigen::Index n, const std::string& detail) {
  std::ostringstream os;
  os << "dualcell::linalg Cholesky " << to_string(phase) << " failed";
  if (n >= 0) os << " (n=" << n << ")";
  os << ": " << to_string(status);
  if (!detail.empty()) os << ": " << detail;
  return os.str();
}

}  // namespace

CholeskyError::CholeskyError(CholeskyStatus status, CholeskyPhase phase, Eigen::Index n, const std::string& detail,
                             Eigen::Index column, Eigen::Index original_column)
    : std::runtime_error(make_what(status, phase, n, detail)),
      status_(status),
      phase_(phase),
      n_(n),
      column_(column),
      original_column_(original_column) {}

// ==========================================================================
// Error recording
// ==========================================================================

namespace {

// CHOLMOD's error_handler gets no user pointer, so the handler writes into a
// per-thread record; CholmodCommon::begin_call()/end_call() bracket every
// CHOLMOD call and harvest it.  CHOLMOD calls are synchronous, hence a
// thread_local record cannot be confused between instances.  (Should CHOLMOD
// ever report from a worker thread, only the text would be lost: the status
// is always read from Common->status.)  The handler is
// called from C code and must not throw: fixed buffers, snprintf only.
struct ErrorRecord {
  bool set = false;
  int status = 0;
  int line = 0;
  char file[96] = {};
  char message[256] = {};
};

thread_local ErrorRecord tls_record;

void record_cholmod_error(int status, const char* file, int line, const char* message) {
  ErrorRecord& r = tls_record;
  // Keep the first report, unless a failure follows a warning.
  if (r.set && !(status < 0 && r.status >= 0)) return;
  r.set = true;
  r.status = status;
  r.line = line;
  const char* base = file != nullptr ? file : "?";
  if (const char* slash = std::strrchr(base, '/')) base = slash + 1;
  std::snprintf(r.file, sizeof r.file, "%s", base);
  std::snprintf(r.message, sizeof r.message, "%s", message != nullptr ? message : "");
}

}  // namespace

// ==========================================================================
// CholmodCommon
// ==========================================================================

void CholmodCommon::Deleter::operator()(cholmod_common_struct* c) const noexcept {
  if (c == nullptr) return;
  cholmod_finish(c);
  delete c;
}

CholmodCommon::CholmodCommon(const CholmodOptions& options) : options_(options) {
  auto* raw = new cholmod_common;
  if (!cholmod_start(raw)) {  // only fails for a NULL argument
    delete raw;
    throw CholeskyError(CholeskyStatus::internal_error, CholeskyPhase::setup, -1, "cholmod_start failed");
  }
  common_.reset(raw);
  cholmod_common* c = common_.get();

  c->print = 0;  // CHOLMOD prints nothing; errors go to the handler
  c->error_handler = &record_cholmod_error;

  switch (options.factor_kind) {
    case FactorKind::supernodal:
      c->supernodal = CHOLMOD_SUPERNODAL;
      break;
    case FactorKind::simplicial:
      c->supernodal = CHOLMOD_SIMPLICIAL;
      break;
    case FactorKind::automatic:
      c->supernodal = CHOLMOD_AUTO;
      break;
  }
  // Simplicial factorization is LL^T (not CHOLMOD's default LDL^T): an LDL^T
  // without pivoting "succeeds" on many indefinite matrices, an LL^T fails
  // at the first non-positive pivot, as the supernodal one does.
  c->final_ll = 1;
  // We throw on NOT_POSDEF anyway: do not finish the remaining supernodes.
  c->quick_return_if_not_posdef = 1;

  switch (options.ordering) {
    case Ordering::automatic:
      c->nmethods = 0;  // CHOLMOD default strategy
      break;
    case Ordering::amd:
      c->nmethods = 1;
      c->method[0].ordering = CHOLMOD_AMD;
      c->postorder = 1;
      break;
    case Ordering::metis:
      c->nmethods = 1;
      c->method[0].ordering = CHOLMOD_METIS;
      c->postorder = 1;
      break;
    case Ordering::natural:
      c->nmethods = 1;
      c->method[0].ordering = CHOLMOD_NATURAL;
      c->postorder = 0;  // a postorder would permute after all
      break;
  }
}

CholmodCommon::~CholmodCommon() = default;

CholmodCommon::CholmodCommon(CholmodCommon&& other) noexcept
    : common_(std::move(other.common_)), options_(other.options_), message_(std::move(other.message_)) {}

CholmodCommon& CholmodCommon::operator=(CholmodCommon&& other) noexcept {
  if (this != &other) {
    common_ = std::move(other.common_);
    options_ = other.options_;
    message_ = std::move(other.message_);
  }
  return *this;
}

void CholmodCommon::begin_call() noexcept {
  tls_record.set = false;
  tls_record.status = CHOLMOD_OK;
  message_.clear();
  if (common_) common_->status = CHOLMOD_OK;
}

int CholmodCommon::end_call() {
  const int s = raw_status();
  if (tls_record.set) {
    std::ostringstream os;
    os << "CHOLMOD: " << tls_record.message << " [status " << tls_record.status << ", " << tls_record.file << ':'
       << tls_record.line << ']';
    message_ = os.str();
    tls_record.set = false;
  }
  return s;
}

int CholmodCommon::raw_status() const noexcept { return common_ ? common_->status : CHOLMOD_INVALID; }

CholeskyStatus CholmodCommon::status() const noexcept { return status_from_cholmod(raw_status()); }

// ==========================================================================
// SparseCholesky
// ==========================================================================

namespace {

// Non-null stand-ins for the index/value arrays of a matrix without stored
// entries (Eigen may then hold null pointers, which CHOLMOD rejects).
int dummy_index = 0;
double dummy_value = 0.0;

// Zero-copy CHOLMOD view of an Eigen column-major matrix, lower triangle
// (stype = -1).  CHOLMOD does not write to A in analyze/factorize; the
// const_casts only satisfy its non-const C signatures.
cholmod_sparse lower_view(const SparseCholesky::SparseMatrix& A) {
  cholmod_sparse s{};
  const auto n = static_cast<std::size_t>(A.cols());
  s.nrow = static_cast<std::size_t>(A.rows());
  s.ncol = n;
  s.p = const_cast<int*>(A.outerIndexPtr());
  s.packed = A.isCompressed() ? 1 : 0;
  s.nz = A.isCompressed() ? nullptr : const_cast<int*>(A.innerNonZeroPtr());
  const std::size_t stored = n > 0 ? static_cast<std::size_t>(A.outerIndexPtr()[n]) : 0;
  s.nzmax = std::max<std::size_t>(stored, 1);
  s.i = A.innerIndexPtr() != nullptr ? const_cast<int*>(A.innerIndexPtr()) : &dummy_index;
  s.x = A.valuePtr() != nullptr ? const_cast<double*>(A.valuePtr()) : &dummy_value;
  s.z = nullptr;
  s.stype = -1;
  s.itype = CHOLMOD_INT;
  s.xtype = CHOLMOD_REAL;
  s.dtype = CHOLMOD_DOUBLE;
  // Eigen keeps inner indices sorted, but nothing here depends on it.
  s.sorted = 0;
  return s;
}

// [begin, end) of the stored entries of column j (compressed or not).
inline std::pair<int, int> column_range(const SparseCholesky::SparseMatrix& A, Eigen::Index j) {
  const int* p = A.outerIndexPtr();
  const int b = p[j];
  const int e = A.isCompressed() ? p[j + 1] : b + A.innerNonZeroPtr()[j];
  return {b, e};
}

std::string size_mismatch(const char* what, Eigen::Index got_r, Eigen::Index got_c, Eigen::Index want) {
  std::ostringstream os;
  os << what << " is " << got_r << 'x' << got_c << ", expected " << want << " rows";
  return os.str();
}

}  // namespace

SparseCholesky::SparseCholesky(const CholmodOptions& options) : options_(options), common_(options) {}

SparseCholesky::~SparseCholesky() { release(); }

SparseCholesky::SparseCholesky(SparseCholesky&& o) noexcept
    : options_(o.options_),
      common_(std::move(o.common_)),
      factor_(std::exchange(o.factor_, nullptr)),
      ws_(std::exchange(o.ws_, Workspace{})),
      n_(std::exchange(o.n_, 0)),
      analyzed_(std::exchange(o.analyzed_, false)),
      factorized_(std::exchange(o.factorized_, false)),
      pattern_ptr_(std::move(o.pattern_ptr_)),
      pattern_idx_(std::move(o.pattern_idx_)),
      marker_(std::move(o.marker_)),
      last_status_(std::exchange(o.last_status_, CholeskyStatus::ok)),
      last_message_(std::move(o.last_message_)) {}

SparseCholesky& SparseCholesky::operator=(SparseCholesky&& o) noexcept {
  if (this == &o) return *this;
  release();  // with our own common, which allocated our factor
  options_ = o.options_;
  common_ = std::move(o.common_);
  factor_ = std::exchange(o.factor_, nullptr);
  ws_ = std::exchange(o.ws_, Workspace{});
  n_ = std::exchange(o.n_, 0);
  analyzed_ = std::exchange(o.analyzed_, false);
  factorized_ = std::exchange(o.factorized_, false);
  pattern_ptr_ = std::move(o.pattern_ptr_);
  pattern_idx_ = std::move(o.pattern_idx_);
  marker_ = std::move(o.marker_);
  last_status_ = std::exchange(o.last_status_, CholeskyStatus::ok);
  last_message_ = std::move(o.last_message_);
  return *this;
}

void SparseCholesky::free_workspace(Workspace& ws) noexcept {
  cholmod_common* c = common_.get();
  if (c == nullptr) return;  // moved-from: nothing can be owned
  cholmod_free_dense(&ws.X, c);
  cholmod_free_dense(&ws.Y, c);
  cholmod_free_dense(&ws.E, c);
}

void SparseCholesky::release() noexcept {
  cholmod_common* c = common_.get();
  if (c == nullptr) return;
  free_workspace(ws_);
  if (factor_ != nullptr) cholmod_free_factor(&factor_, c);
  factor_ = nullptr;
  analyzed_ = false;
  factorized_ = false;
}

void SparseCholesky::require_common(CholeskyPhase phase) const {
  if (!common_.valid())
    throw CholeskyError(CholeskyStatus::invalid_input, phase, -1, "SparseCholesky object was moved from");
}

void SparseCholesky::require_factorized(CholeskyPhase phase) const {
  require_common(phase);
  if (!factorized_)
    throw CholeskyError(CholeskyStatus::invalid_input, phase, n_,
                        analyzed_ ? "no valid numeric factorization (factorize() not called "
                                    "or it failed)"
                                  : "analyze() and factorize() not called");
}

void SparseCholesky::throw_cholmod(CholeskyPhase phase, int raw, const char* what) {
  last_message_ = common_.last_message();
  CholeskyStatus st = status_from_cholmod(raw);
  std::string detail = what;
  if (st == CholeskyStatus::ok || st == CholeskyStatus::numerical_warning) {
    // The call returned failure without a failure status.
    st = CholeskyStatus::internal_error;
    detail += " returned failure with status " + std::to_string(raw);
  }
  if (!last_message_.empty()) detail += "; " + last_message_;
  last_status_ = st;
  throw CholeskyError(st, phase, n_, detail);
}

void SparseCholesky::check_lower_storage(const SparseMatrix& A, CholeskyPhase phase) const {
  // Upper-only storage would silently be read as a diagonal matrix.
  std::int64_t strictly_lower = 0, strictly_upper = 0;
  for (Eigen::Index j = 0; j < A.cols(); ++j) {
    const auto [b, e] = column_range(A, j);
    const int* idx = A.innerIndexPtr();
    for (int p = b; p < e; ++p) {
      if (idx[p] > j)
        ++strictly_lower;
      else if (idx[p] < j)
        ++strictly_upper;
    }
  }
  if (strictly_upper > 0 && strictly_lower == 0)
    throw CholeskyError(CholeskyStatus::invalid_input, phase, A.rows(),
                        "matrix has only upper-triangular off-diagonal entries; only the "
                        "lower triangle is read (pass full or lower storage)");
}

void SparseCholesky::analyze(const SparseMatrix& pattern, std::span<const int> last) {
  constexpr auto phase = CholeskyPhase::analyze;
  require_common(phase);
  if (pattern.rows() != pattern.cols()) {
    last_status_ = CholeskyStatus::invalid_input;
    throw CholeskyError(
        CholeskyStatus::invalid_input, phase, pattern.rows(),
        "matrix is not square (" + std::to_string(pattern.rows()) + "x" + std::to_string(pattern.cols()) + ")");
  }
  try {
    check_lower_storage(pattern, phase);
  } catch (...) {
    last_status_ = CholeskyStatus::invalid_input;
    throw;
  }
  for (int j : last)
    if (j < 0 || j >= pattern.rows()) {
      last_status_ = CholeskyStatus::invalid_input;
      throw CholeskyError(CholeskyStatus::invalid_input, phase, pattern.rows(),
                          "column " + std::to_string(j) + " to order last is out of range");
    }
  release();
  last_status_ = CholeskyStatus::ok;
  last_message_.clear();
  n_ = pattern.rows();

  // Keep the lower pattern for the subset check in factorize().
  pattern_ptr_.assign(static_cast<std::size_t>(n_) + 1, 0);
  pattern_idx_.clear();
  for (Eigen::Index j = 0; j < n_; ++j) {
    const auto [b, e] = column_range(pattern, j);
    const int* idx = pattern.innerIndexPtr();
    for (int p = b; p < e; ++p)
      if (idx[p] >= j) pattern_idx_.push_back(idx[p]);
    pattern_ptr_[static_cast<std::size_t>(j) + 1] = static_cast<int>(pattern_idx_.size());
  }
  marker_.assign(static_cast<std::size_t>(n_), -1);

  if (n_ == 0) {  // nothing for CHOLMOD to do
    analyzed_ = true;
    return;
  }

  cholmod_sparse A = lower_view(pattern);
  cholmod_common* c = common_.get();
  cholmod_factor* L = nullptr;
  int raw = CHOLMOD_OK;
  if (last.empty()) {
    common_.begin_call();
    L = cholmod_analyze(&A, c);
    raw = common_.end_call();
  } else {
    // CAMD with two constraint sets (0 first, 1 last), then that order as given: no other
    // ordering tried and no postorder, which could move a `last` column forward.
    std::vector<int> member(static_cast<std::size_t>(n_), 0), perm(static_cast<std::size_t>(n_));
    for (int j : last) member[static_cast<std::size_t>(j)] = 1;
    const int nmethods = c->nmethods, ordering = c->method[0].ordering, postorder = c->postorder;
    common_.begin_call();
    if (cholmod_camd(&A, nullptr, 0, member.data(), perm.data(), c)) {
      c->nmethods = 1;
      c->method[0].ordering = CHOLMOD_GIVEN;
      c->postorder = 0;
      L = cholmod_analyze_p(&A, perm.data(), nullptr, 0, c);
      c->nmethods = nmethods, c->method[0].ordering = ordering, c->postorder = postorder;
    }
    raw = common_.end_call();
  }
  if (L == nullptr || raw < CHOLMOD_OK) {
    if (L != nullptr) cholmod_free_factor(&L, c);
    throw_cholmod(phase, raw, "cholmod_analyze");
  }
  factor_ = L;
  analyzed_ = true;
  last_status_ = status_from_cholmod(raw);
  last_message_ = common_.last_message();
}

void SparseCholesky::check_pattern_subset(const SparseMatrix& A) {
  // marker_[i] == j  <=>  row i is in analyzed column j.  Marks left over
  // from an earlier call are marks of the same analyzed pattern, so they
  // never produce a false "present".
  const int* idx = A.innerIndexPtr();
  for (Eigen::Index j = 0; j < n_; ++j) {
    const auto jj = static_cast<int>(j);
    for (int p = pattern_ptr_[j]; p < pattern_ptr_[j + 1]; ++p) marker_[pattern_idx_[p]] = jj;
    const auto [b, e] = column_range(A, j);
    for (int p = b; p < e; ++p) {
      const int i = idx[p];
      if (i >= jj && marker_[i] != jj) {
        last_status_ = CholeskyStatus::invalid_input;
        throw CholeskyError(CholeskyStatus::invalid_input, CholeskyPhase::factorize, n_,
                            "entry (" + std::to_string(i) + ", " + std::to_string(j) +
                                ") is not in the lower pattern given to analyze()");
      }
    }
  }
}

CholeskyStatus SparseCholesky::factorize(const SparseMatrix& matrix) {
  constexpr auto phase = CholeskyPhase::factorize;
  require_common(phase);
  if (!analyzed_) {
    last_status_ = CholeskyStatus::invalid_input;
    throw CholeskyError(CholeskyStatus::invalid_input, phase, matrix.rows(), "analyze() not called");
  }
  if (matrix.rows() != n_ || matrix.cols() != n_) {
    last_status_ = CholeskyStatus::invalid_input;
    throw CholeskyError(CholeskyStatus::invalid_input, phase, n_,
                        "matrix is " + std::to_string(matrix.rows()) + "x" + std::to_string(matrix.cols()) +
                            ", analyzed order is " + std::to_string(n_));
  }
  // Argument checks first: a rejected call leaves the current factor usable.
  try {
    check_lower_storage(matrix, phase);
  } catch (...) {
    last_status_ = CholeskyStatus::invalid_input;
    throw;
  }
  check_pattern_subset(matrix);
  factorized_ = false;
  last_message_.clear();

  if (n_ == 0) {
    factorized_ = true;
    last_status_ = CholeskyStatus::ok;
    return last_status_;
  }

  cholmod_sparse A = lower_view(matrix);
  cholmod_common* c = common_.get();
  common_.begin_call();
  const int ok = cholmod_factorize(&A, factor_, c);
  const int raw = common_.end_call();

  if (raw == CHOLMOD_NOT_POSDEF) {
    last_message_ = common_.last_message();
    last_status_ = CholeskyStatus::not_positive_definite;
    const auto minor = static_cast<Eigen::Index>(factor_->minor);
    Eigen::Index original = minor;
    if (factor_->Perm != nullptr && minor >= 0 && minor < n_) original = static_cast<const int*>(factor_->Perm)[minor];
    std::ostringstream os;
    os << "leading minor of order " << minor + 1 << " is not positive (failing column " << minor
       << " of the permuted matrix = column " << original << " of the input)";
    if (!last_message_.empty()) os << "; " << last_message_;
    throw CholeskyError(CholeskyStatus::not_positive_definite, phase, n_, os.str(), minor, original);
  }
  if (!ok || raw < CHOLMOD_OK) throw_cholmod(phase, raw, "cholmod_factorize");

  factorized_ = true;
  CholeskyStatus st = status_from_cholmod(raw);  // ok or numerical_warning
  last_message_ = common_.last_message();

  common_.begin_call();
  const double rcond = cholmod_rcond(factor_, c);
  (void)common_.end_call();
  if (options_.rcond_warning_threshold > 0.0 && !(rcond >= options_.rcond_warning_threshold)) {
    st = CholeskyStatus::numerical_warning;
    std::ostringstream os;
    os << "rcond estimate " << rcond << " below threshold " << options_.rcond_warning_threshold;
    if (!last_message_.empty()) os << "; " << last_message_;
    last_message_ = os.str();
  }
  last_status_ = st;
  return st;
}

SparseCholesky::TriangularFactor SparseCholesky::triangular_factor() {
  require_factorized(CholeskyPhase::solve);
  TriangularFactor out;
  out.L.resize(n_, n_);
  out.perm.resize(static_cast<std::size_t>(n_));
  if (n_ == 0) return out;
  cholmod_common* c = common_.get();
  const auto free_copy = [c](cholmod_factor* f) { cholmod_free_factor(&f, c); };
  common_.begin_call();
  const std::unique_ptr<cholmod_factor, decltype(free_copy)> owned(cholmod_copy_factor(factor_, c), free_copy);
  cholmod_factor* copy = owned.get();
  // Simplicial, LLᵀ, packed and monotonic: column j's entries are p[j] .. p[j+1]-1, the
  // diagonal first, rows ascending (CHOLMOD's simplicial layout).
  const int ok = copy != nullptr && cholmod_change_factor(CHOLMOD_REAL, /*to_ll=*/1, /*to_super=*/0, /*to_packed=*/1,
                                                          /*to_monotonic=*/1, copy, c);
  const int raw = common_.end_call();
  if (!ok || raw < CHOLMOD_OK) throw_cholmod(CholeskyPhase::solve, raw, "cholmod_change_factor");
  const int* p = static_cast<const int*>(copy->p);
  const int* i = static_cast<const int*>(copy->i);
  const double* x = static_cast<const double*>(copy->x);
  const int* perm = static_cast<const int*>(copy->Perm);
  const int nnz = p[n_];
  out.L.resizeNonZeros(nnz);
  std::copy_n(p, n_ + 1, out.L.outerIndexPtr());
  std::copy_n(i, nnz, out.L.innerIndexPtr());
  std::copy_n(x, nnz, out.L.valuePtr());
  for (Eigen::Index k = 0; k < n_; ++k)
    out.perm[static_cast<std::size_t>(k)] = perm != nullptr ? perm[k] : static_cast<int>(k);
  return out;
}

CholeskyStatus SparseCholesky::compute(const SparseMatrix& matrix, std::span<const int> last) {
  analyze(matrix, last);
  return factorize(matrix);
}

void SparseCholesky::solve_impl(const double* b, double* x) {
  Workspace& ws = ws_;
  cholmod_dense B{};
  B.nrow = static_cast<std::size_t>(n_);
  B.ncol = 1;
  B.nzmax = B.nrow * B.ncol;
  B.d = B.nrow;
  B.x = const_cast<double*>(b);  // read only by cholmod_solve2
  B.z = nullptr;
  B.xtype = CHOLMOD_REAL;
  B.dtype = CHOLMOD_DOUBLE;

  common_.begin_call();
  const int ok = cholmod_solve2(CHOLMOD_A, factor_, &B, nullptr, &ws.X, nullptr, &ws.Y, &ws.E, common_.get());
  const int raw = common_.end_call();
  if (!ok || raw < CHOLMOD_OK || ws.X == nullptr) {
    const CholeskyStatus keep = last_status_;
    const std::string keep_msg = last_message_;
    try {
      throw_cholmod(CholeskyPhase::solve, raw, "cholmod_solve2");
    } catch (...) {
      last_status_ = keep;  // solve() does not change last_status()
      last_message_ = keep_msg;
      throw;
    }
  }
  // CHOLMOD 5.x quirk: the simplicial path of cholmod_solve2 asks for
  // Y = max(4, k) x n (k = 1 here), but its internal ptrans() reshapes Y in
  // place to 1 x n, so the next call finds a "wrong" shape and reallocates Y
  // every time.  Restore the
  // header; only the header is touched, and only if Y's buffer (nzmax)
  // really holds that shape, so this is memory-safe for any CHOLMOD version.
  if (!factor_->is_super && ws.Y != nullptr) {
    const std::size_t nr = std::max<std::size_t>(4, B.ncol);
    if (ws.Y->ncol == B.nrow && ws.Y->nzmax >= nr * B.nrow) {
      ws.Y->nrow = nr;
      ws.Y->d = nr;
    }
  }
  // X has leading dimension n (cholmod_solve2 ensures d == n).
  std::copy_n(static_cast<const double*>(ws.X->x), B.nzmax, x);
}

void SparseCholesky::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  require_factorized(CholeskyPhase::solve);
  if (b.size() != n_)
    throw CholeskyError(CholeskyStatus::invalid_input, CholeskyPhase::solve, n_,
                        size_mismatch("right-hand side", b.size(), 1, n_));
  if (n_ == 0) {
    x.resize(0);
    return;
  }
  // If b and x alias, the resize is a no-op (sizes match) and CHOLMOD has
  // read all of B before X is copied out.
  x.resize(n_);
  solve_impl(b.data(), x.data());
}

}  // namespace dualcell::linalg
