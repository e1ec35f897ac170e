#include "qp/dense_qp.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

namespace dualcell::qp {

namespace {

// A pivot below this fraction of the largest entry of the equilibrated KKT matrix: the free
// set's system is singular (A not positive definite on ker C, or a variable that no row can move).
constexpr double singular_pivot = 1e-13;
// Rows of C_F independent to this fraction of its largest column norm (QR with column pivoting
// of C_Fᵀ): a fibre whose rows are all held at bounds leaves its rows of C with no free column.
constexpr double independent_row = 1e-10;
// A bound's multiplier of the wrong sign by less than this fraction of the terms that make it
// up is round-off: releasing it would let the variable move by round-off and be caught again.
constexpr double multiplier_round_off = 1e-10;
// A free variable whose unit vector has this share of its length outside the row space of C_F
// (an orthonormal basis, so only round-off) is pinned by C.
constexpr double pinned_round_off = 1e-8;
// A step of a free variable below this fraction of the size of x is round-off.
constexpr double round_off_move = 1e-12;
// Corrections of the warm start before the method falls back to x = 0.
constexpr int max_guesses = 6;
// A subproblem's solution this close to its bounds (relative to its own size, in each variable's
// unit) is feasible: round-off of the LU solve, far below any step the method takes.
constexpr double feasibility_slack = 1e-12;

}  // namespace

DenseActiveSet::DenseActiveSet(const Eigen::MatrixXd& A, const Eigen::MatrixXd& C) : A_(A), C_(C) {}

void DenseActiveSet::free_a_basis() {
  const Eigen::MatrixXd& C = C_;
  const Eigen::Index n = C.cols(), n_c = C.rows();
  if (n_c == 0) return;
  // An orthonormal basis Q of the span of the free columns of C, then every held column that
  // adds to that span is freed (it stays where it is: a free variable may sit on its bound).
  Eigen::MatrixXd Q(n_c, n_c);
  int rank = 0;
  const double scale = std::max(C.cwiseAbs().maxCoeff(), std::numeric_limits<double>::min());
  const auto add = [&](Eigen::Index i) {
    if (rank == n_c) return false;
    Eigen::VectorXd v = C.col(i);
    for (int pass = 0; pass < 2; ++pass) v -= Q.leftCols(rank) * (Q.leftCols(rank).transpose() * v);
    if (v.norm() <= independent_row * scale) return false;
    Q.col(rank++) = v.normalized();
    return true;
  };
  for (Eigen::Index i = 0; i < n; ++i)
    if (working_[i] == Bound::free) add(i);
  for (Eigen::Index i = 0; i < n && rank < n_c; ++i)
    if (working_[i] != Bound::free && add(i)) working_[i] = Bound::free;
}

void DenseActiveSet::factorise() {
  const Eigen::MatrixXd &A = A_, &C = C_;
  const Eigen::Index n = A.rows(), n_c = C.rows();
  free_.clear();
  for (Eigen::Index i = 0; i < n; ++i)
    if (working_[i] == Bound::free) free_.push_back(static_cast<int>(i));
  const int n_F = static_cast<int>(free_.size());
  kept_rows_.clear();
  pinned_.assign(n_F, 0);
  if (n_c > 0 && n_F > 0) {
    Eigen::MatrixXd CFt(n_F, n_c);
    for (int j = 0; j < n_F; ++j) CFt.row(j) = C.col(free_[j]).transpose();
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(CFt);
    qr.setThreshold(independent_row);
    for (Eigen::Index k = 0; k < qr.rank(); ++k) kept_rows_.push_back(qr.colsPermutation().indices()(k));
    std::sort(kept_rows_.begin(), kept_rows_.end());
    // A free variable is pinned where e_j lies in the row space of C_F (orthonormal basis: the
    // first rank columns of Q): C_F d = 0 then forces d_j = 0, so it never moves, and holding
    // it would make the working set dependent (its multiplier meaningless).
    const Eigen::MatrixXd basis = qr.householderQ() * Eigen::MatrixXd::Identity(n_F, qr.rank());
    for (int j = 0; j < n_F; ++j) pinned_[j] = basis.row(j).squaredNorm() > 1 - pinned_round_off;
  }
  const int r = static_cast<int>(kept_rows_.size()), k = n_F + r;
  if (kkt_.rows() < k) kkt_.resize(std::max<Eigen::Index>(k, n + n_c), std::max<Eigen::Index>(k, n + n_c));
  if (static_cast<int>(pivot_.size()) < k) pivot_.resize(n + n_c);
  // The system is factorised equilibrated, S K S with S diagonal: 1/√A_jj on a free variable
  // (A_jj > 0 on every variable a row can move), 1/‖(C S)_q‖ on a kept row. The scaled A block
  // has a unit diagonal whatever the units of the variables (a cell's macro stresses beside its
  // interface forces, its flexibility in any length unit), so the singular-pivot test below
  // compares like with like; unscaled, a block 10¹³ smaller than another read as singular.
  if (static_cast<int>(kkt_scale_.size()) < k) kkt_scale_.resize(std::max<Eigen::Index>(k, n + n_c));
  for (int j = 0; j < n_F; ++j) {
    const double d = A(free_[j], free_[j]);
    kkt_scale_(j) = d > 0 && std::isfinite(d) ? 1 / std::sqrt(d) : 1.0;
  }
  for (int q = 0; q < r; ++q) {
    double norm = 0;
    for (int j = 0; j < n_F; ++j) norm = std::hypot(norm, C(kept_rows_[q], free_[j]) * kkt_scale_(j));
    kkt_scale_(n_F + q) = norm > 0 ? 1 / norm : 1.0;
  }
  auto K = kkt_.topLeftCorner(k, k);
  K.setZero();
  for (int j = 0; j < n_F; ++j)
    for (int i = 0; i < n_F; ++i) K(i, j) = kkt_scale_(i) * A(free_[i], free_[j]) * kkt_scale_(j);
  for (int q = 0; q < r; ++q)
    for (int j = 0; j < n_F; ++j)
      K(n_F + q, j) = K(j, n_F + q) = kkt_scale_(n_F + q) * C(kept_rows_[q], free_[j]) * kkt_scale_(j);
  // LU with partial pivoting, in place (L unit lower, U upper), by panels of `panel` columns:
  // each panel factorised column by column, then the rows to its right solved with its L and
  // the trailing block updated by one matrix product (the work of a few hundred rows is in that
  // product, several times faster than rank-one updates). Row swaps act on whole rows, so that
  // lu_solve applies them in order before the two triangular solves.
  constexpr int panel = 32;
  const double largest = k > 0 ? K.cwiseAbs().maxCoeff() : 0.0;
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
  generation_ = ++generations_;
}

bool DenseActiveSet::take_kept(const std::vector<int>& free) {
  ++uses_;
  const auto swap_with = [&](Kept& e) {
    std::swap(free_, e.free);
    std::swap(kept_rows_, e.kept_rows);
    std::swap(pivot_, e.pivot);
    std::swap(pinned_, e.pinned);
    kkt_.swap(e.kkt);
    kkt_scale_.swap(e.kkt_scale);
    std::swap(generation_, e.generation);
    e.last_used = uses_;
  };
  for (Kept& e : kept_)
    if (e.free == free) {
      const bool was_factorised = factorised_;
      swap_with(e);
      factorised_ = true;
      if (!was_factorised) e.free.clear(), e.free.push_back(-1);  // no free set matches: unused
      return true;
    }
  if (!factorised_) return false;
  const std::size_t entry_bytes = sizeof(double) * static_cast<std::size_t>(kkt_.size()) + 64;
  const std::size_t capacity = std::min(max_kept, kept_bytes / entry_bytes);
  if (capacity == 0) return false;
  if (kept_.size() < capacity) {
    kept_.emplace_back();
    swap_with(kept_.back());
  } else {
    swap_with(*std::min_element(kept_.begin(), kept_.end(),
                                [](const Kept& a, const Kept& b) { return a.last_used < b.last_used; }));
  }
  return false;
}

void DenseActiveSet::lu_solve(Eigen::VectorXd& rhs) const {
  // K x = rhs as (S K S)(S⁻¹ x) = S rhs.
  const int k = static_cast<int>(rhs.size());
  rhs.array() *= kkt_scale_.head(k).array();
  for (int j = 0; j < k; ++j)
    if (pivot_[j] != j) std::swap(rhs(j), rhs(pivot_[j]));
  const auto K = kkt_.topLeftCorner(k, k);
  K.triangularView<Eigen::UnitLower>().solveInPlace(rhs);
  K.triangularView<Eigen::Upper>().solveInPlace(rhs);
  rhs.array() *= kkt_scale_.head(k).array();
}

void DenseActiveSet::solve_subproblem(const Eigen::VectorXd& b, const Eigen::VectorXd& x, Eigen::VectorXd& x_free,
                                      Eigen::VectorXd& mu) const {
  const Eigen::MatrixXd &A = A_, &C = C_;
  const int n_F = static_cast<int>(free_.size()), r = static_cast<int>(kept_rows_.size());
  // The right-hand side b_F − A_FW x_W and −C_KW x_W over the held columns W only (A symmetric).
  Eigen::VectorXd& rhs = rhs_;
  rhs.resize(n_F + r);
  for (int j = 0; j < n_F; ++j) rhs(j) = b(free_[j]);
  rhs.tail(r).setZero();
  for (Eigen::Index w = 0; w < x.size(); ++w) {
    if (working_[w] == Bound::free || x(w) == 0) continue;
    for (int j = 0; j < n_F; ++j) rhs(j) -= A(free_[j], w) * x(w);
    for (int q = 0; q < r; ++q) rhs(n_F + q) -= C(kept_rows_[q], w) * x(w);
  }
  lu_solve(rhs);
  x_free = rhs.head(n_F);
  mu = Eigen::VectorXd::Zero(C.rows());
  for (int q = 0; q < r; ++q) mu(kept_rows_[q]) = rhs(n_F + q);
}

namespace {

// The working set `set` and x at its bounds; a bound that is infinite cannot hold a variable.
void hold(const Eigen::VectorXd& l, const Eigen::VectorXd& u, std::vector<Bound>& set, Eigen::VectorXd& x) {
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    if (l(i) == u(i)) set[i] = Bound::lower;  // a fixed variable is held from the start
    if (set[i] == Bound::lower && !std::isfinite(l(i))) set[i] = Bound::free;
    if (set[i] == Bound::upper && !std::isfinite(u(i))) set[i] = Bound::free;
    x(i) = set[i] == Bound::lower ? l(i) : set[i] == Bound::upper ? u(i) : x(i);
  }
}

}  // namespace

bool DenseActiveSet::refactorise(DenseQpResult& out) {
  // The kept factorisation serves while the free set is the same (A and C are this object's).
  bool same = factorised_;
  if (same) {
    int j = 0;
    for (Eigen::Index i = 0; i < A_.rows() && same; ++i)
      if (working_[i] == Bound::free) same = j < static_cast<int>(free_.size()) && free_[j++] == i;
    same = same && j == static_cast<int>(free_.size());
  }
  if (!same) {
    std::vector<int> free;
    for (Eigen::Index i = 0; i < A_.rows(); ++i)
      if (working_[i] == Bound::free) free.push_back(static_cast<int>(i));
    if (!take_kept(free)) {
      factorise();
      ++out.factorisations;
    }
  }
  return factorised_;
}

double DenseActiveSet::scaled_size(const Eigen::VectorXd& x, const Eigen::VectorXd& x_free) const {
  double size = 0;
  for (std::size_t j = 0; j < free_.size(); ++j)
    size = std::max(size, (std::abs(x(free_[j])) + std::abs(x_free(j))) / kkt_scale_(static_cast<Eigen::Index>(j)));
  return size;
}

bool DenseActiveSet::feasible(const Eigen::VectorXd& l, const Eigen::VectorXd& u, const Eigen::VectorXd& x,
                              const Eigen::VectorXd& x_free) const {
  // Round-off of the solve in each variable's own unit: the scaled solution's size times its scale
  // (an absolute slack of 1e-12 was a sixth of the forces of a cell of size 1e-10).
  const double size = scaled_size(x, x_free);
  for (std::size_t j = 0; j < free_.size(); ++j) {
    const int i = free_[j];
    const double slack = feasibility_slack * (std::abs(x_free(j)) + kkt_scale_(static_cast<Eigen::Index>(j)) * size);
    if (x_free(j) < l(i) - slack || x_free(j) > u(i) + slack) return false;
  }
  return true;
}

bool DenseActiveSet::warm_start(const Eigen::VectorXd& b, const Eigen::VectorXd& l, const Eigen::VectorXd& u,
                                Eigen::VectorXd& x, Eigen::VectorXd& x_free, Eigen::VectorXd& mu, DenseQpResult& out) {
  const Eigen::MatrixXd &A = A_, &C = C_;
  const Eigen::Index n = A.rows();
  for (int guess = 0; guess <= max_guesses; ++guess) {
    hold(l, u, working_, x);
    free_a_basis();
    if (!refactorise(out)) break;
    solve_subproblem(b, x, x_free, mu);
    ++out.iterations;
    if (feasible(l, u, x, x_free)) {
      for (std::size_t j = 0; j < free_.size(); ++j) x(free_[j]) = std::clamp(x_free(j), l(free_[j]), u(free_[j]));
      return true;
    }
    Eigen::VectorXd trial = x;
    for (std::size_t j = 0; j < free_.size(); ++j) trial(free_[j]) = x_free(j);
    Eigen::VectorXd nu = A * trial - b;
    if (C.rows() > 0) nu.noalias() += C.transpose() * mu;
    for (Eigen::Index i = 0; i < n; ++i) {
      if (working_[i] == Bound::free) {
        if (trial(i) < l(i)) working_[i] = Bound::lower;
        if (trial(i) > u(i)) working_[i] = Bound::upper;
      } else if ((working_[i] == Bound::lower && nu(i) < 0) || (working_[i] == Bound::upper && nu(i) > 0)) {
        if (l(i) != u(i)) working_[i] = Bound::free;
      }
    }
  }
  return false;
}

bool DenseActiveSet::step_towards(const Eigen::VectorXd& l, const Eigen::VectorXd& u, const Eigen::VectorXd& x_free,
                                  Eigen::VectorXd& x) {
  // A move of round-off size (a variable the rows of C pin, at 0 up to round-off) blocks
  // nothing: holding it would make the working set dependent. Round-off in each variable's own
  // unit (the equilibration's scale): a cell's macro stresses and its interface forces differ
  // by the cell's size, and one size for all made the forces of a small cell round-off.
  const double size = scaled_size(x, x_free);
  double step = 1;
  int blocking = -1;
  Bound blocking_bound = Bound::free;
  for (std::size_t j = 0; j < free_.size(); ++j) {
    const int i = free_[j];
    double d = x_free(j) - x(i);
    if (pinned_[j] || std::abs(d) <= round_off_move * kkt_scale_(static_cast<Eigen::Index>(j)) * size) d = 0;
    if (d < 0 && std::isfinite(l(i)) && (l(i) - x(i)) / d < step)
      step = std::max(0.0, (l(i) - x(i)) / d), blocking = i, blocking_bound = Bound::lower;
    if (d > 0 && std::isfinite(u(i)) && (u(i) - x(i)) / d < step)
      step = std::max(0.0, (u(i) - x(i)) / d), blocking = i, blocking_bound = Bound::upper;
  }
  for (std::size_t j = 0; j < free_.size(); ++j)
    if (!pinned_[j]) x(free_[j]) += step * (x_free(j) - x(free_[j]));
  if (blocking < 0) return false;
  working_[blocking] = blocking_bound;
  x(blocking) = blocking_bound == Bound::lower ? l(blocking) : u(blocking);
  return true;
}

int DenseActiveSet::bound_to_release(const Eigen::VectorXd& b, const Eigen::VectorXd& l, const Eigen::VectorXd& u,
                                     const Eigen::VectorXd& x, const Eigen::VectorXd& mu,
                                     Eigen::VectorXd& nu_out) const {
  const Eigen::MatrixXd &A = A_, &C = C_;
  const Eigen::Index n = A.rows();
  nu_out.setZero(n);
  int release = -1;
  double worst = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    if (working_[i] == Bound::free) continue;
    double nu = A.col(i).dot(x) - b(i), terms = A.col(i).cwiseAbs().dot(x.cwiseAbs()) + std::abs(b(i));
    if (C.rows() > 0) nu += C.col(i).dot(mu), terms += C.col(i).cwiseAbs().dot(mu.cwiseAbs());
    nu_out(i) = nu;
    if (l(i) == u(i)) continue;  // a fixed variable: its multiplier has either sign
    const double wrong = working_[i] == Bound::lower ? -nu : nu;
    const double relative = wrong / std::max(terms, std::numeric_limits<double>::min());
    if (relative > multiplier_round_off && relative > worst) worst = relative, release = static_cast<int>(i);
  }
  return release;
}

DenseQpResult DenseActiveSet::solve(const Eigen::VectorXd& b, const Eigen::VectorXd& l, const Eigen::VectorXd& u,
                                    std::vector<Bound>& active) {
  const Eigen::MatrixXd &A = A_, &C = C_;
  DenseQpResult out;
  const Eigen::Index n = A.rows();
  if (A.cols() != n || b.size() != n || l.size() != n || u.size() != n || (C.rows() > 0 && C.cols() != n)) {
    out.message = "sizes do not match";
    return out;
  }
  if ((l.array() > 0).any() || (u.array() < 0).any()) {
    out.message = "x = 0 is not within the bounds";
    return out;
  }
  if (static_cast<Eigen::Index>(active.size()) != n) active.assign(n, Bound::free);

  Eigen::VectorXd x = Eigen::VectorXd::Zero(n), x_free, mu;
  // Warm start: the given set (none: every variable free) and up to max_guesses corrections of it
  // in the manner of block principal pivoting (Júdice & Pires): a variable its subproblem puts
  // beyond a bound is held there, a held one whose multiplier has the wrong sign is freed. The
  // first guess whose subproblem's solution is feasible starts the primal method; along a path
  // that is usually the given set itself, one solve.
  working_ = active;
  bool at_subproblem_solution = warm_start(b, l, u, x, x_free, mu, out);
  if (!at_subproblem_solution) {
    // Cold start from x = 0, every variable with a bound at zero held there: the method then
    // releases what the multipliers ask for (a step from 0 towards a free subproblem's solution
    // would be blocked at once by every such variable, one per iteration).
    x.setZero();
    for (Eigen::Index i = 0; i < n; ++i)
      working_[i] = l(i) == 0 ? Bound::lower : u(i) == 0 ? Bound::upper : Bound::free;
    free_a_basis();
  }

  const int max_iterations = 10 * static_cast<int>(n) + 50;
  while (out.iterations <= max_iterations) {
    if (!at_subproblem_solution) {
      if (!refactorise(out)) {
        out.message = "the KKT system of the free set is singular (A not positive definite on ker C)";
        return out;
      }
      solve_subproblem(b, x, x_free, mu);
      ++out.iterations;
      // Step from x towards the subproblem's solution, as far as the bounds allow; a bound met
      // joins the working set and the next subproblem is solved.
      if (step_towards(l, u, x_free, x)) continue;
      at_subproblem_solution = true;
    }
    // At the subproblem's solution: the multipliers of the held bounds (zero where free), each
    // counted as wrong only beyond the round-off of the terms that make it up. Held variables
    // only: n per held variable, nothing for a problem with none held.
    const int release = bound_to_release(b, l, u, x, mu, out.nu);
    if (release < 0) {
      out.x = x;
      out.mu = mu;
      out.converged = true;
      active = working_;
      return out;
    }
    working_[release] = Bound::free;
    at_subproblem_solution = false;
  }
  out.message = "no solution within " + std::to_string(max_iterations) + " active-set iterations (cycling)";
  out.x = x;
  return out;
}

Eigen::MatrixXd DenseActiveSet::sensitivity(const Eigen::MatrixXd& db) const {
  Eigen::MatrixXd dx = Eigen::MatrixXd::Zero(db.rows(), db.cols());
  if (!factorised_) return dx;
  const int n_F = static_cast<int>(free_.size()), r = static_cast<int>(kept_rows_.size()), k = n_F + r;
  // All columns at once: the triangular solves with a block right-hand side.
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(k, db.cols());
  for (int j = 0; j < n_F; ++j) rhs.row(j) = kkt_scale_(j) * db.row(free_[j]);
  for (int j = 0; j < k; ++j)
    if (pivot_[j] != j) rhs.row(j).swap(rhs.row(pivot_[j]));
  const auto K = kkt_.topLeftCorner(k, k);
  K.triangularView<Eigen::UnitLower>().solveInPlace(rhs);
  K.triangularView<Eigen::Upper>().solveInPlace(rhs);
  for (int j = 0; j < n_F; ++j) dx.row(free_[j]) = kkt_scale_(j) * rhs.row(j);
  return dx;
}

}  // namespace dualcell::qp
