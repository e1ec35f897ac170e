#include "qp/dense_qp.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

namespace dualcell::qp {

namespace {

// A bound's multiplier of the wrong sign by less than this fraction of the terms that make it
// up is round-off: releasing it would let the variable move by round-off and be caught again.
constexpr double multiplier_round_off = 1e-10;
// A step of a free variable below this fraction of the size of x is round-off.
constexpr double round_off_move = 1e-12;
// Corrections of the warm start before the method falls back to x = 0.
constexpr int max_guesses = 6;
// A subproblem's solution this close to its bounds (relative to its own size, in each variable's
// unit) is feasible: round-off of the LU solve, far below any step the method takes.
constexpr double feasibility_slack = 1e-12;

}  // namespace

DenseActiveSet::DenseActiveSet(const Eigen::MatrixXd& A, const Eigen::MatrixXd& C, Updates updates)
    : A_(A), C_(C), updates_(updates), C_rank_(rank_of_rows(C)) {}

void DenseActiveSet::solve_subproblem(const Eigen::VectorXd& b, const Eigen::VectorXd& x, Eigen::VectorXd& x_free,
                                      Eigen::VectorXd& mu) const {
  const Eigen::MatrixXd &A = A_, &C = C_;
  const int n_F0 = static_cast<int>(base_free_.size()), r = static_cast<int>(base_rows_.size());
  const int k0 = n_F0 + r, t = static_cast<int>(border_.size());
  // The right-hand side in the bordered unknowns (kkt_solve): b − A x_W and −C x_W over the held
  // columns W outside the base only (A symmetric); a held base variable's border row asks for
  // its value, an added variable's row is b_a − A_aW x_W.
  Eigen::MatrixXd& rhs = rhs_;
  rhs.resize(k0 + t, 1);
  for (int j = 0; j < n_F0; ++j) rhs(j, 0) = b(base_free_[j]);
  rhs.col(0).segment(n_F0, r).setZero();
  for (int s = 0; s < t; ++s) rhs(k0 + s, 0) = border_added_[s] ? b(border_[s]) : x(border_[s]);
  for (Eigen::Index w = 0; w < x.size(); ++w) {
    if (working_[w] == Bound::free || x(w) == 0 || base_index_[w] >= 0) continue;
    for (int j = 0; j < n_F0; ++j) rhs(j, 0) -= A(base_free_[j], w) * x(w);
    for (int q = 0; q < r; ++q) rhs(n_F0 + q, 0) -= C(base_rows_[q], w) * x(w);
    for (int s = 0; s < t; ++s)
      if (border_added_[s]) rhs(k0 + s, 0) -= A(border_[s], w) * x(w);
  }
  kkt_solve(rhs);
  const int n_F = static_cast<int>(free_.size());
  x_free.resize(n_F);
  for (int j = 0; j < n_F; ++j) x_free(j) = rhs(position_[j], 0);
  mu = Eigen::VectorXd::Zero(C.rows());
  for (int q = 0; q < r; ++q) mu(base_rows_[q]) = rhs(n_F0 + q, 0);
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

double DenseActiveSet::scaled_size(const Eigen::VectorXd& x, const Eigen::VectorXd& x_free) const {
  double size = 0;
  for (std::size_t j = 0; j < free_.size(); ++j)
    size = std::max(size, (std::abs(x(free_[j])) + std::abs(x_free(j))) / free_scale_(static_cast<Eigen::Index>(j)));
  return size;
}

bool DenseActiveSet::feasible(const Eigen::VectorXd& l, const Eigen::VectorXd& u, const Eigen::VectorXd& x,
                              const Eigen::VectorXd& x_free) const {
  // Round-off of the solve in each variable's own unit: the scaled solution's size times its scale
  // (an absolute slack of 1e-12 was a sixth of the forces of a cell of size 1e-10).
  const double size = scaled_size(x, x_free);
  for (std::size_t j = 0; j < free_.size(); ++j) {
    const int i = free_[j];
    const double slack = feasibility_slack * (std::abs(x_free(j)) + free_scale_(static_cast<Eigen::Index>(j)) * size);
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
    if (pinned_[j] || std::abs(d) <= round_off_move * free_scale_(static_cast<Eigen::Index>(j)) * size) d = 0;
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
  // in the manner of block principal pivoting (docs/method.md §16a): a variable its subproblem puts
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

}  // namespace dualcell::qp
