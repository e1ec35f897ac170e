// The KKT systems of the dense active-set method (qp/dense_qp.hpp): the factorisation of a free
// set (the base), the bordered solves of free sets near it, and the kept earlier bases.
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

#include "qp/dense_qp.hpp"

namespace dualcell::qp {

namespace {

// A pivot below this fraction of the largest entry of the equilibrated KKT matrix: the free
// set's system is singular (A not positive definite on ker C, or a variable that no row can move).
constexpr double singular_pivot = 1e-13;
// Rows of C_F independent to this fraction of its largest column norm (QR with column pivoting
// of C_Fᵀ): a fibre whose rows are all held at bounds leaves its rows of C with no free column.
constexpr double independent_row = 1e-10;
// A free variable whose unit vector has this share of its length outside the row space of C_F
// (an orthonormal basis, so only round-off) is pinned by C.
constexpr double pinned_round_off = 1e-8;
// free_a_basis: free columns whose Gram matrix has eigenvalues within this ratio span C's rows
// (a condition of 10³ against the 10¹⁰ of independent_row): nothing is to be freed.
constexpr double well_spanned = 1e-6;
// Bordered solves (docs/method.md §16a). Below min_bordered unknowns a factorisation costs about
// what a border's bookkeeping does, and the kept factorisations serve better (with 16 the default
// scene's 16-row small cell took 6.7 µs per state along the cantilever's paths against 3.5);
// beyond max_border variables the border's columns (2k² each)
// and its Schur complement (t²k) approach the ⅔k³ of a factorisation, and the round-off of the
// Schur complement grows with it, so the free set gets a factorisation of its own.
constexpr int min_bordered = 64;
constexpr int max_border = 32;
// The Schur complement of the border is singular when its LU's pivots fall below this fraction of
// the larger of 1 and its largest pivot: the system is equilibrated (the base's A block and a
// freed variable's diagonal are 1), so a freed variable that A cannot hold on ker C leaves a pivot
// of round-off, whatever the others are. The bordered system is then singular or too
// ill-conditioned to trust, and a factorisation of the free set itself decides.
constexpr double schur_singular = 1e-10;
// Every set bordered on a base inherits its conditioning: a base whose smallest LU pivot is below
// this fraction of its largest entry (it passed singular_pivot, 1e-13) is not bordered on.
constexpr double well_conditioned_base = 1e-8;

// The equilibration of a free variable: 1/√A_jj (A_jj > 0 on every variable a row can move).
double variable_scale(double a_jj) { return a_jj > 0 && std::isfinite(a_jj) ? 1 / std::sqrt(a_jj) : 1.0; }

// One Gram–Schmidt step (two passes) of the column v against the orthonormal basis Q(:, 0..rank):
// v joins it where what is left of it exceeds independent_row × `scale` (C's largest entry).
// w is the workspace of the projections (size ≥ rank).
bool extend_basis(Eigen::MatrixXd& Q, int& rank, Eigen::VectorXd& v, Eigen::VectorXd& w, double scale) {
  for (int pass = 0; pass < 2; ++pass) {
    w.head(rank).noalias() = Q.leftCols(rank).transpose() * v;
    v.noalias() -= Q.leftCols(rank) * w.head(rank);
  }
  if (v.norm() <= independent_row * scale) return false;
  Q.col(rank++) = v.normalized();
  return true;
}

// C's largest entry, the unit of extend_basis's threshold.
double basis_scale(const Eigen::MatrixXd& C) {
  return std::max(C.cwiseAbs().maxCoeff(), std::numeric_limits<double>::min());
}

}  // namespace

int DenseActiveSet::rank_of_rows(const Eigen::MatrixXd& C) {
  // free_a_basis's Gram–Schmidt over every column, with its threshold: the rank it can reach.
  const Eigen::Index n_c = C.rows();
  if (n_c == 0) return 0;
  Eigen::MatrixXd Q(n_c, n_c);
  Eigen::VectorXd v, w(n_c);
  int rank = 0;
  const double scale = basis_scale(C);
  for (Eigen::Index i = 0; i < C.cols() && rank < n_c; ++i) {
    v = C.col(i);
    extend_basis(Q, rank, v, w, scale);
  }
  return rank;
}

void DenseActiveSet::free_a_basis() {
  const Eigen::MatrixXd& C = C_;
  const Eigen::Index n = C.cols(), n_c = C.rows();
  if (n_c == 0) return;
  // An orthonormal basis Q of the span of the free columns of C, then every held column that
  // adds to that span is freed (it stays where it is: a free variable may sit on its bound).
  // Both passes stop once the span has C's rank (rows of C may be dependent), and the workspace
  // is the object's: a cell's rows of C each see one fibre, so the span is full only at the last
  // fibre's columns, and a vector allocated per column made this 39 % of a structure's time.
  const double scale = basis_scale(C);
  // The common case first: the free columns span C's rows with room to spare (the smallest
  // eigenvalue of their Gram matrix C_F C_Fᵀ at least well_spanned times the largest, a condition
  // of 10³ where the test below needs 10¹⁰, and its square root 100 times the test's absolute
  // threshold), so nothing is to be freed.
  if (C_rank_ == n_c) {
    Eigen::MatrixXd& CF = basis_CF_;
    CF.resize(n_c, n);
    Eigen::Index n_F = 0;
    for (Eigen::Index i = 0; i < n; ++i)
      if (working_[i] == Bound::free) CF.col(n_F++) = C.col(i);
    basis_gram_.resize(n_c, n_c);
    basis_gram_.noalias() = CF.leftCols(n_F) * CF.leftCols(n_F).transpose();
    basis_eigen_.compute(basis_gram_, Eigen::EigenvaluesOnly);
    const Eigen::VectorXd& lambda = basis_eigen_.eigenvalues();  // ascending
    const double floor = 100 * independent_row * scale;
    if (basis_eigen_.info() == Eigen::Success && lambda(0) >= well_spanned * lambda(n_c - 1) &&
        lambda(0) > floor * floor)
      return;
  }
  Eigen::MatrixXd& Q = basis_Q_;
  Eigen::VectorXd &v = basis_v_, &w = basis_w_;
  Q.resize(n_c, n_c);
  w.resize(n_c);
  int rank = 0;
  const auto add = [&](Eigen::Index i) {
    v = C.col(i);
    return extend_basis(Q, rank, v, w, scale);
  };
  for (Eigen::Index i = 0; i < n && rank < C_rank_; ++i)
    if (working_[i] == Bound::free) add(i);
  for (Eigen::Index i = 0; i < n && rank < C_rank_; ++i)
    if (working_[i] != Bound::free && add(i)) working_[i] = Bound::free;
}

void DenseActiveSet::rows_of_free_set(const std::vector<int>& free, std::vector<int>& rows,
                                      std::vector<char>& pinned) const {
  const Eigen::MatrixXd& C = C_;
  const int n_F = static_cast<int>(free.size());
  const Eigen::Index n_c = C.rows();
  rows.clear();
  pinned.assign(n_F, 0);
  if (n_c == 0 || n_F == 0) return;
  Eigen::MatrixXd CFt(n_F, n_c);
  for (int j = 0; j < n_F; ++j) CFt.row(j) = C.col(free[j]).transpose();
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(CFt);
  qr.setThreshold(independent_row);
  for (Eigen::Index k = 0; k < qr.rank(); ++k) rows.push_back(qr.colsPermutation().indices()(k));
  std::sort(rows.begin(), rows.end());
  // A free variable is pinned where e_j lies in the row space of C_F (orthonormal basis: the
  // first rank columns of Q): C_F d = 0 then forces d_j = 0, so it never moves, and holding
  // it would make the working set dependent (its multiplier meaningless).
  const Eigen::MatrixXd basis = qr.householderQ() * Eigen::MatrixXd::Identity(n_F, qr.rank());
  for (int j = 0; j < n_F; ++j) pinned[j] = basis.row(j).squaredNorm() > 1 - pinned_round_off;
}

void DenseActiveSet::factorise() {
  const Eigen::MatrixXd &A = A_, &C = C_;
  const Eigen::Index n = A.rows(), n_c = C.rows();
  base_free_ = free_;
  rows_of_free_set(base_free_, base_rows_, base_pinned_);
  const int n_F = static_cast<int>(base_free_.size());
  const int r = static_cast<int>(base_rows_.size()), k = n_F + r;
  if (kkt_.rows() < k) kkt_.resize(std::max<Eigen::Index>(k, n + n_c), std::max<Eigen::Index>(k, n + n_c));
  if (static_cast<int>(pivot_.size()) < k) pivot_.resize(n + n_c);
  // The system is factorised equilibrated, S K S with S diagonal: 1/√A_jj on a free variable,
  // 1/‖(C S)_q‖ on a kept row. The scaled A block has a unit diagonal whatever the units of the
  // variables (a cell's macro stresses beside its interface forces, its flexibility in any length
  // unit), so the singular-pivot test below compares like with like; unscaled, a block 10¹³
  // smaller than another read as singular.
  if (static_cast<int>(kkt_scale_.size()) < k) kkt_scale_.resize(std::max<Eigen::Index>(k, n + n_c));
  for (int j = 0; j < n_F; ++j) kkt_scale_(j) = variable_scale(A(base_free_[j], base_free_[j]));
  for (int q = 0; q < r; ++q) {
    double norm = 0;
    for (int j = 0; j < n_F; ++j) norm = std::hypot(norm, C(base_rows_[q], base_free_[j]) * kkt_scale_(j));
    kkt_scale_(n_F + q) = norm > 0 ? 1 / norm : 1.0;
  }
  auto K = kkt_.topLeftCorner(k, k);
  K.setZero();
  for (int j = 0; j < n_F; ++j)
    for (int i = 0; i < n_F; ++i) K(i, j) = kkt_scale_(i) * A(base_free_[i], base_free_[j]) * kkt_scale_(j);
  for (int q = 0; q < r; ++q)
    for (int j = 0; j < n_F; ++j)
      K(n_F + q, j) = K(j, n_F + q) = kkt_scale_(n_F + q) * C(base_rows_[q], base_free_[j]) * kkt_scale_(j);
  // LU with partial pivoting, in place (L unit lower, U upper), by panels of `panel` columns:
  // each panel factorised column by column, then the rows to its right solved with its L and
  // the trailing block updated by one matrix product (the work of a few hundred rows is in that
  // product, several times faster than rank-one updates). Row swaps act on whole rows, so that
  // base_solve applies them in order before the two triangular solves.
  constexpr int panel = 32;
  const double largest = k > 0 ? K.cwiseAbs().maxCoeff() : 0.0;
  double smallest = std::numeric_limits<double>::infinity();
  for (int j0 = 0; j0 < k; j0 += panel) {
    const int jb = std::min(panel, k - j0), end = j0 + jb;
    for (int j = j0; j < end; ++j) {
      Eigen::Index p;
      const double pivot = K.col(j).tail(k - j).cwiseAbs().maxCoeff(&p);
      p += j;
      if (!(pivot > singular_pivot * largest)) {
        factorised_ = false;
        return;
      }
      smallest = std::min(smallest, pivot);
      pivot_[j] = static_cast<int>(p);
      if (p != j) K.row(j).swap(K.row(p));
      K.col(j).tail(k - j - 1) /= K(j, j);
      K.block(j + 1, j + 1, k - j - 1, end - j - 1).noalias() -=
          K.col(j).tail(k - j - 1) * K.row(j).segment(j + 1, end - j - 1);
    }
    if (end == k) break;
    K.block(j0, j0, jb, jb).triangularView<Eigen::UnitLower>().solveInPlace(K.block(j0, end, jb, k - end));
    K.bottomRightCorner(k - end, k - end).noalias() -= K.block(end, j0, k - end, jb) * K.block(j0, end, jb, k - end);
  }
  factorised_ = true;
  base_pivot_ratio_ = k > 0 ? smallest / largest : 1.0;
  base_generation_ = ++generations_;
  current_is_base();
}

void DenseActiveSet::current_is_base() {
  free_ = base_free_;
  kept_rows_ = base_rows_;
  pinned_ = base_pinned_;
  const int n_F = static_cast<int>(base_free_.size());
  free_scale_ = kkt_scale_.head(n_F);
  border_.clear();
  border_added_.clear();
  position_.resize(n_F);
  for (int j = 0; j < n_F; ++j) position_[j] = j;
  base_index_.assign(A_.rows(), -1);
  for (int j = 0; j < n_F; ++j) base_index_[base_free_[j]] = j;
  generation_ = base_generation_;
}

void DenseActiveSet::swap_base(Kept& e) {
  std::swap(base_free_, e.free);
  std::swap(base_rows_, e.kept_rows);
  std::swap(pivot_, e.pivot);
  std::swap(base_pinned_, e.pinned);
  kkt_.swap(e.kkt);
  kkt_scale_.swap(e.kkt_scale);
  std::swap(base_generation_, e.generation);
  std::swap(base_pivot_ratio_, e.pivot_ratio);
  e.last_used = uses_;
}

bool DenseActiveSet::take_kept(const std::vector<int>& free) {
  ++uses_;
  for (Kept& e : kept_)
    if (e.free == free) {
      const bool was_factorised = factorised_;
      swap_base(e);
      factorised_ = true;
      if (!was_factorised) e.free.clear(), e.free.push_back(-1), e.last_used = 0;  // unused: the first to go
      current_is_base();
      return true;
    }
  return false;
}

void DenseActiveSet::store_base() {
  if (!factorised_) return;
  const std::size_t entry_bytes = sizeof(double) * static_cast<std::size_t>(kkt_.size()) + 64;
  const std::size_t capacity = std::min(max_kept, kept_bytes / entry_bytes);
  if (capacity == 0) return;
  if (kept_.size() < capacity) {
    kept_.emplace_back();
    swap_base(kept_.back());
  } else {
    swap_base(*std::min_element(kept_.begin(), kept_.end(),
                                [](const Kept& a, const Kept& b) { return a.last_used < b.last_used; }));
  }
  factorised_ = false;  // the base now holds what the entry held
}

bool DenseActiveSet::border(const std::vector<int>& free) {
  const Eigen::MatrixXd &A = A_, &C = C_;
  const int n_F0 = static_cast<int>(base_free_.size()), r0 = static_cast<int>(base_rows_.size());
  const int k0 = n_F0 + r0;
  if (k0 < min_bordered || base_pivot_ratio_ < well_conditioned_base) return false;
  // The border: the base's variables now held, and the variables now free that it does not have
  // (both lists sorted, so one merge).
  std::vector<int> vars;
  std::vector<char> added;
  for (std::size_t i = 0, j = 0; i < free.size() || j < base_free_.size();) {
    if (j == base_free_.size() || (i < free.size() && free[i] < base_free_[j])) {
      vars.push_back(free[i++]), added.push_back(1);
    } else if (i == free.size() || base_free_[j] < free[i]) {
      vars.push_back(base_free_[j++]), added.push_back(0);
    } else {
      ++i, ++j;
    }
    if (static_cast<int>(vars.size()) > max_border) return false;
  }
  if (vars.empty()) {  // back at the base's own free set
    current_is_base();
    return true;
  }
  std::vector<int> rows;
  std::vector<char> pinned;
  rows_of_free_set(free, rows, pinned);
  if (rows != base_rows_) {
    // Where the rows of C are dependent (a 16-fibre RVE's), the QR may pick other independent
    // rows for the same row space: the base's rows serve when they alone have its rank over the
    // new free set (they then span every row there).
    if (rows.size() != base_rows_.size()) return false;
    Eigen::MatrixXd CFt(free.size(), base_rows_.size());
    for (std::size_t j = 0; j < free.size(); ++j)
      for (std::size_t q = 0; q < base_rows_.size(); ++q) CFt(j, q) = C(base_rows_[q], free[j]);
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(CFt);
    qr.setThreshold(independent_row);
    if (qr.rank() != static_cast<Eigen::Index>(base_rows_.size())) return false;
    rows = base_rows_;
  }
  const int t = static_cast<int>(vars.size());
  Eigen::MatrixXd B, Z;
  Eigen::VectorXd scale;
  border_columns(vars, added, B, Z, scale);
  Eigen::MatrixXd D = Eigen::MatrixXd::Zero(t, t);
  for (int s = 0; s < t; ++s)
    for (int q = 0; q < t; ++q)
      if (added[s] && added[q]) D(s, q) = scale(s) * A(vars[s], vars[q]) * scale(q);
  D.noalias() -= B.transpose() * Z;
  const Eigen::FullPivLU<Eigen::MatrixXd> schur(D);
  const Eigen::VectorXd pivots = schur.matrixLU().diagonal().cwiseAbs();
  if (!(pivots.minCoeff() > schur_singular * std::max(1.0, pivots.maxCoeff()))) return false;
  schur_ = schur;
  border_ = std::move(vars);
  border_added_ = std::move(added);
  border_scale_ = scale;
  border_B_.swap(B);
  border_Z_.swap(Z);
  free_ = free;
  kept_rows_ = std::move(rows);
  pinned_ = std::move(pinned);
  const int n_F = static_cast<int>(free_.size());
  free_scale_.resize(n_F);
  position_.resize(n_F);
  for (int j = 0; j < n_F; ++j) {
    const int v = free_[j];
    if (base_index_[v] >= 0) {
      position_[j] = base_index_[v];
      free_scale_(j) = kkt_scale_(base_index_[v]);
    } else {
      const int s = static_cast<int>(std::find(border_.begin(), border_.end(), v) - border_.begin());
      position_[j] = k0 + s;
      free_scale_(j) = border_scale_(s);
    }
  }
  generation_ = ++generations_;
  return true;
}

void DenseActiveSet::border_columns(const std::vector<int>& vars, const std::vector<char>& added, Eigen::MatrixXd& B,
                                    Eigen::MatrixXd& Z, Eigen::VectorXd& scale) const {
  const Eigen::MatrixXd &A = A_, &C = C_;
  const int n_F0 = static_cast<int>(base_free_.size()), r0 = static_cast<int>(base_rows_.size());
  const int k0 = n_F0 + r0, t = static_cast<int>(vars.size());
  B.resize(k0, t);
  Z.resize(k0, t);
  scale.resize(t);
  for (int s = 0; s < t; ++s) {
    const int v = vars[s];
    scale(s) = added[s] ? variable_scale(A(v, v)) : 1 / kkt_scale_(base_index_[v]);
    const auto old = std::find(border_.begin(), border_.end(), v);
    if (old != border_.end() && border_added_[old - border_.begin()] == added[s]) {
      B.col(s) = border_B_.col(old - border_.begin());
      Z.col(s) = border_Z_.col(old - border_.begin());
      continue;
    }
    B.col(s).setZero();
    if (added[s]) {
      for (int j = 0; j < n_F0; ++j) B(j, s) = kkt_scale_(j) * A(base_free_[j], v) * scale(s);
      for (int q = 0; q < r0; ++q) B(n_F0 + q, s) = kkt_scale_(n_F0 + q) * C(base_rows_[q], v) * scale(s);
    } else {
      B(base_index_[v], s) = 1;
    }
    Z.col(s) = B.col(s);
    base_solve(Z.col(s));
  }
}

void DenseActiveSet::base_solve(Eigen::Ref<Eigen::MatrixXd> v) const {
  const int k = static_cast<int>(v.rows());
  for (int j = 0; j < k; ++j)
    if (pivot_[j] != j) v.row(j).swap(v.row(pivot_[j]));
  const auto K = kkt_.topLeftCorner(k, k);
  if (v.cols() == 1) {  // one column: the vector kernels (the matrix ones cost twice as much)
    auto x = v.col(0);
    K.triangularView<Eigen::UnitLower>().solveInPlace(x);
    K.triangularView<Eigen::Upper>().solveInPlace(x);
    return;
  }
  K.triangularView<Eigen::UnitLower>().solveInPlace(v);
  K.triangularView<Eigen::Upper>().solveInPlace(v);
}

void DenseActiveSet::kkt_solve(Eigen::Ref<Eigen::MatrixXd> v) const {
  // [K̂ B̂; B̂ᵀ D̂] in the equilibrated unknowns, (S K S)(S⁻¹ x) = S rhs: with y = K̂⁻¹ v₀, the border's
  // z = (D̂ − B̂ᵀẐ)⁻¹ (v₁ − B̂ᵀ y) and the base's y − Ẑ z (B̂ᵀ K̂⁻¹ = Ẑᵀ, K̂ being symmetric).
  const int k0 = static_cast<int>(base_free_.size() + base_rows_.size()), t = static_cast<int>(border_.size());
  auto base = v.topRows(k0);
  auto edge = v.bottomRows(t);
  base.array().colwise() *= kkt_scale_.head(k0).array();
  if (t > 0) {
    edge.array().colwise() *= border_scale_.array();
    if (v.cols() == 1)
      edge.col(0).noalias() -= border_Z_.transpose() * base.col(0);
    else
      edge.noalias() -= border_Z_.transpose() * base;
  }
  base_solve(base);
  if (t > 0) {
    edge = schur_.solve(Eigen::MatrixXd(edge));
    if (v.cols() == 1)
      base.col(0).noalias() -= border_Z_ * edge.col(0);
    else
      base.noalias() -= border_Z_ * edge;
    edge.array().colwise() *= border_scale_.array();
  }
  base.array().colwise() *= kkt_scale_.head(k0).array();
}

bool DenseActiveSet::refactorise(DenseQpResult& out) {
  std::vector<int>& free = next_free_;
  free.clear();
  for (Eigen::Index i = 0; i < A_.rows(); ++i)
    if (working_[i] == Bound::free) free.push_back(static_cast<int>(i));
  // The current system serves while the free set is the same (A and C are this object's); then a
  // kept base of this very free set, then a border on the base, then a factorisation of its own.
  if (factorised_ && free == free_) return true;
  if (take_kept(free)) return true;
  if (factorised_ && updates_ == Updates::bordered && border(free)) {
    ++out.updates;
    return true;
  }
  store_base();
  free_ = free;
  factorise();
  ++out.factorisations;
  return factorised_;
}

Eigen::MatrixXd DenseActiveSet::sensitivity(const Eigen::MatrixXd& db) const {
  Eigen::MatrixXd dx = Eigen::MatrixXd::Zero(db.rows(), db.cols());
  if (!factorised_) return dx;
  // All columns at once: the held variables do not move (their border rows ask for 0).
  const int n_F0 = static_cast<int>(base_free_.size()), k0 = n_F0 + static_cast<int>(base_rows_.size());
  const int t = static_cast<int>(border_.size());
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(k0 + t, db.cols());
  for (int j = 0; j < n_F0; ++j) rhs.row(j) = db.row(base_free_[j]);
  for (int s = 0; s < t; ++s) {
    if (border_added_[s])
      rhs.row(k0 + s) = db.row(border_[s]);
    else
      rhs.row(base_index_[border_[s]]).setZero();  // its multiplier takes what it is asked
  }
  kkt_solve(rhs);
  for (std::size_t j = 0; j < free_.size(); ++j) dx.row(free_[j]) = rhs.row(position_[j]);
  return dx;
}

}  // namespace dualcell::qp
