#include "law/fused_cell.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace dualcell::law {

namespace {

constexpr double inf = std::numeric_limits<double>::infinity();

// The onset φ(N) = max_k g_k·N over the facets' rows (−inf without any).
double onset_measure_of(const Eigen::MatrixXd& facets, const Eigen::VectorXd& N) {
  return facets.rows() > 0 ? (facets * N).maxCoeff() : -inf;
}

// Whether x is a convex combination of the columns of P and the origin (x = Pλ, λ ≥ 0, Σλ ≤ 1),
// to `tolerance` in the units of x: phase one of the simplex method on the n + 1 equality rows
// (the last one Σλ + s = 1 with its slack s), an artificial variable per row, Bland's rule (no
// cycling). A few pivots: n + 1 ≤ 4 rows.
bool in_hull_with_origin(const Eigen::MatrixXd& P, const Eigen::VectorXd& x, double tolerance) {
  const int n = static_cast<int>(P.rows()), k = static_cast<int>(P.cols()), rows = n + 1;
  const int cols = k + 1 + rows;  // λ, s, artificials; then the right-hand side
  Eigen::MatrixXd T = Eigen::MatrixXd::Zero(rows, cols + 1);
  T.topLeftCorner(n, k) = P;
  T.block(n, 0, 1, k).setOnes();
  T(n, k) = 1;
  T.col(cols).head(n) = x;
  T(n, cols) = 1;
  for (int i = 0; i < rows; ++i) {
    if (T(i, cols) < 0) T.row(i) *= -1;
    T(i, k + 1 + i) = 1;
  }
  std::vector<int> basis(static_cast<std::size_t>(rows));
  for (int i = 0; i < rows; ++i) basis[static_cast<std::size_t>(i)] = k + 1 + i;
  const double pivot_floor = 1e-12;
  for (int iteration = 0; iteration < 50 * cols; ++iteration) {
    // Reduced costs of minimising the artificials' sum: minus the column's sum over the rows
    // whose basic variable is artificial.
    int entering = -1;
    for (int j = 0; j < k + 1 && entering < 0; ++j) {
      double cost = 0;
      for (int i = 0; i < rows; ++i)
        if (basis[static_cast<std::size_t>(i)] > k) cost -= T(i, j);
      if (cost < -pivot_floor) entering = j;
    }
    if (entering < 0) break;
    int leaving = -1;
    double ratio = inf;
    for (int i = 0; i < rows; ++i) {
      if (T(i, entering) <= pivot_floor) continue;
      const double r = T(i, cols) / T(i, entering);
      if (r < ratio || (r == ratio && basis[static_cast<std::size_t>(i)] < basis[static_cast<std::size_t>(leaving)]))
        ratio = r, leaving = i;
    }
    if (leaving < 0) break;  // cannot happen while the artificials bound the sum
    T.row(leaving) /= T(leaving, entering);
    for (int i = 0; i < rows; ++i)
      if (i != leaving) T.row(i) -= T(i, entering) * T.row(leaving);
    basis[static_cast<std::size_t>(leaving)] = entering;
  }
  double infeasibility = 0;
  for (int i = 0; i < rows; ++i)
    if (basis[static_cast<std::size_t>(i)] > k) infeasibility += T(i, cols);
  return infeasibility <= tolerance;
}

}  // namespace

CondensedCell debonded_cell(const CondensedCell& cell) {
  CondensedCell out = cell;
  out.lower_bonded = cell.lower_broken;
  out.upper_bonded = cell.upper_broken;
  std::fill(out.bonded.begin(), out.bonded.end(), std::uint8_t{0});
  return out;
}

BondedCell bonded_cell(const CondensedCell& cell) {
  const int n = cell.n_macro;
  CellEvaluator evaluator(cell);
  BondedCell out;
  out.S.resize(n, n);
  Eigen::MatrixXd A(cell.n_rows(), n);  // bond forces per unit macro stress
  for (int j = 0; j < n; ++j) {
    Eigen::Vector3d N = Eigen::Vector3d::Zero();
    N(j) = 1;
    const double onset = evaluator.onset(N);
    const double s = std::isfinite(onset) ? 0.5 * onset : 1.0;
    CellHistory history = evaluator.unloaded();
    const CellResponse r = evaluator.at_stress(s * N, history);
    if (!r.ok || r.broken > 0)
      throw std::invalid_argument("the bonded cell's response to unit stress " + std::to_string(j) +
                                  (r.ok ? " breaks a bond below its onset" : " failed: " + r.message));
    out.S.col(j) = r.strain.head(n) / s;
    A.col(j) = r.forces / s;
  }
  out.S = 0.5 * (out.S + out.S.transpose());
  // Each finite strength bound of a bonded row is a facet: a_r·σ̄ = bound.
  std::vector<Eigen::VectorXd> facets;
  for (int r = 0; r < cell.n_rows(); ++r) {
    if (!cell.bonded[static_cast<std::size_t>(cell.pair[static_cast<std::size_t>(r)])]) continue;
    for (const double bound : {cell.lower_bonded(r), cell.upper_bonded(r)})
      if (std::isfinite(bound) && bound != 0) facets.push_back(A.row(r).transpose() / bound);
  }
  out.facets.resize(static_cast<Eigen::Index>(facets.size()), n);
  for (std::size_t k = 0; k < facets.size(); ++k) out.facets.row(static_cast<Eigen::Index>(k)) = facets[k].transpose();
  return out;
}

FusedCell cell_with_fuse(const CondensedCell& cell, const CondensedCell& after) {
  const int n = cell.n_macro;
  if (!cell.adhesion()) throw std::invalid_argument("the cell has no adhesion: it has no fuse");
  if (after.adhesion() || after.n_macro != n || after.volume != cell.volume || !(after.S0 - cell.S0).isZero(0))
    throw std::invalid_argument("the cell past the fuse is not a cell of contact rows with the cell's macro part");
  const BondedCell bonded = bonded_cell(cell);
  FusedCell out;
  out.candidate_facets = static_cast<int>(bonded.facets.rows());

  // The facets on the onset polytope: g_k is one of its facets unless it lies in the convex hull
  // of the origin and the other facets (then g_k·σ̄ ≤ max(0, max_j g_j·σ̄) for every σ̄: another
  // bond always reaches its strength first). Repeats are dropped first (one of two equal facets
  // stays).
  const Eigen::MatrixXd& all = bonded.facets;
  const double scale = all.rows() > 0 ? all.rowwise().norm().maxCoeff() : 1.0;
  std::vector<int> distinct;
  for (int k = 0; k < out.candidate_facets; ++k) {
    bool repeat = all.row(k).norm() <= facet_tolerance * scale;
    for (int j : distinct)
      if (!repeat && (all.row(k) - all.row(j)).norm() <= facet_tolerance * scale) repeat = true;
    if (!repeat) distinct.push_back(k);
  }
  std::vector<int> rows;
  for (std::size_t a = 0; a < distinct.size(); ++a) {
    Eigen::MatrixXd others(n, static_cast<Eigen::Index>(distinct.size()) - 1);
    for (std::size_t b = 0, c = 0; b < distinct.size(); ++b)
      if (b != a) others.col(static_cast<Eigen::Index>(c++)) = all.row(distinct[b]).transpose() / scale;
    if (!in_hull_with_origin(others, all.row(distinct[a]).transpose() / scale, facet_tolerance))
      rows.push_back(distinct[a]);
  }
  const int F = static_cast<int>(rows.size());
  out.facets = F;
  Eigen::MatrixXd G(F, n);
  for (int k = 0; k < F; ++k) G.row(k) = all.row(rows[static_cast<std::size_t>(k)]);
  for (const Eigen::Vector3d& d : sample_directions(n, onset_check_directions)) {
    const Eigen::VectorXd N = d.head(n);
    const double every = onset_measure_of(all, N), kept = onset_measure_of(G, N);
    if (every > 0) out.onset_error = std::max(out.onset_error, std::abs(kept / every - 1));
  }

  // H_bb = Q R⁻ᵀ Δ R⁻¹ Qᵀ + c (I − QQᵀ), Y_b = H_bb G (fused_cell.hpp).
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(G);
  const Eigen::VectorXd R_diagonal =
      F >= n ? Eigen::VectorXd(qr.matrixQR().diagonal().cwiseAbs()) : Eigen::VectorXd::Zero(1);
  if (F < n || R_diagonal.minCoeff() <= 1e-12 * R_diagonal.maxCoeff())
    throw std::invalid_argument(
        "the onset facets do not span the macro stresses: the onset is unbounded along some "
        "direction and the bonded cell cannot carry a fuse there");
  const Eigen::MatrixXd Q = qr.householderQ() * Eigen::MatrixXd::Identity(F, n);
  const Eigen::MatrixXd R = Eigen::MatrixXd(qr.matrixQR()).topRows(n).triangularView<Eigen::Upper>();
  const Eigen::MatrixXd Delta = cell.volume * (cell.S0 - bonded.S);
  const Eigen::MatrixXd Rinv = R.inverse();
  const Eigen::MatrixXd core = Rinv.transpose() * Delta * Rinv;
  Eigen::MatrixXd Hbb = Q * core * Q.transpose();
  Hbb += core.diagonal().maxCoeff() * (Eigen::MatrixXd::Identity(F, F) - Q * Q.transpose());
  Hbb = 0.5 * (Hbb + Hbb.transpose());
  const Eigen::MatrixXd Yb = Hbb * G;
  const Eigen::MatrixXd Yc = after.Y;
  const int m = after.n_rows();
  const Eigen::MatrixXd Hbc = Yb * (cell.volume * cell.S0).llt().solve(Yc.transpose());

  CondensedCell& c = out.cell;
  c.n_macro = n;
  c.volume = cell.volume;
  c.S0 = cell.S0;
  c.Y.resize(F + m, n);
  c.Y << Yb, Yc;
  c.H.resize(F + m, F + m);
  c.H << Hbb, Hbc, Hbc.transpose(), after.H;
  c.G.resize(after.G.rows(), F + m);  // the equality rows of `after` (none for a small cell)
  c.G << Eigen::MatrixXd::Zero(after.G.rows(), F), after.G;
  c.tangential.assign(static_cast<std::size_t>(F), 1);
  c.tangential.insert(c.tangential.end(), after.tangential.begin(), after.tangential.end());
  c.pair.assign(static_cast<std::size_t>(F + m), 0);
  c.n_pairs = 1;
  c.bonded = {1};
  c.lower_bonded.resize(F + m);
  c.upper_bonded.resize(F + m);
  c.lower_broken.resize(F + m);
  c.upper_broken.resize(F + m);
  c.lower_bonded << Eigen::VectorXd::Constant(F, -inf), Eigen::VectorXd::Zero(m);
  c.upper_bonded << Eigen::VectorXd::Ones(F), Eigen::VectorXd::Zero(m);
  c.lower_broken << Eigen::VectorXd::Zero(F), after.lower_broken;
  c.upper_broken << Eigen::VectorXd::Zero(F), after.upper_broken;
  return out;
}

ConeCheck check_along_fuse_paths(const CondensedCell& fused, const CellSample& past_fuse) {
  CellEvaluator evaluator(fused);
  ConeCheck check;
  check.directions = past_fuse.direction;
  double sum = 0;
  int counted = 0;
  for (std::size_t i = 0; i < past_fuse.direction.size(); ++i) {
    if (!past_fuse.strain[i].allFinite()) {  // the exact law has no path here: not counted
      check.error.push_back(std::numeric_limits<double>::quiet_NaN());
      continue;
    }
    CellHistory history = evaluator.unloaded();
    double error = 0;
    const auto at = [&](const Eigen::Vector3d& strain, const Eigen::Vector3d& stress) {
      const CellResponse r = evaluator.at_strain(strain, history);
      const double e = r.ok ? (r.stress - stress).norm() / stress.norm() : inf;
      error = std::max(error, std::isfinite(e) ? e : inf);
    };
    for (std::size_t k = 0; k < past_fuse.path_strain[i].size(); ++k)
      at(past_fuse.path_strain[i][k], past_fuse.path_stress[i][k]);
    at(past_fuse.strain[i], past_fuse.stress[i]);
    check.error.push_back(error);
    sum += error * error;
    ++counted;
    if (error > check.max_error) check.max_error = error, check.worst = past_fuse.direction[i];
  }
  check.rms_error = counted > 0 ? std::sqrt(sum / counted) : std::numeric_limits<double>::quiet_NaN();
  if (counted == 0) check.max_error = std::numeric_limits<double>::quiet_NaN();
  return check;
}

}  // namespace dualcell::law
