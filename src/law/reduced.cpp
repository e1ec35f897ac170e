#include "law/reduced.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "core/progress.hpp"
#include "core/text.hpp"
#include "core/union_find.hpp"
#include "law/bond.hpp"

namespace dualcell::law {

namespace {

// A snapshot repeats a column where their unit vectors differ by less than this.
constexpr double repeat_floor = 1e-6;

// The interface rows grouped by the body they act on: two rows are in one group when a row of G
// (a rigid mode of a fibre) involves both. Each group's part of an admissible p is admissible on
// its own (nonnegative, and G p = 0 holds body by body).
std::vector<std::vector<int>> bodies_of(const CondensedCell& cell) {
  const int n = cell.n_rows();
  UnionFind bodies(n);
  const double floor = 1e-12 * (cell.G.size() > 0 ? cell.G.cwiseAbs().maxCoeff() : 1.0);
  for (Eigen::Index k = 0; k < cell.G.rows(); ++k) {
    int first = -1;
    for (int j = 0; j < n; ++j) {
      if (std::abs(cell.G(k, j)) <= floor) continue;
      if (first < 0)
        first = j;
      else
        bodies.join(j, first);
    }
  }
  std::vector<std::vector<int>> groups;
  std::vector<int> group_of(static_cast<std::size_t>(n), -1);
  for (int i = 0; i < n; ++i) {
    int& g = group_of[static_cast<std::size_t>(bodies.find(i))];
    if (g < 0) g = static_cast<int>(groups.size()), groups.emplace_back();
    groups[static_cast<std::size_t>(g)].push_back(i);
  }
  return groups;
}

}  // namespace

CondensedCell cell_of_rows(const CondensedCell& cell, const Eigen::MatrixXd& Y, const Eigen::MatrixXd& H) {
  const int m = static_cast<int>(Y.rows());
  CondensedCell r;
  r.n_macro = cell.n_macro;
  r.volume = cell.volume;
  r.S0 = cell.S0;
  r.Y = Y;
  r.H = 0.5 * (H + H.transpose());
  r.G.resize(0, m);
  r.tangential.assign(static_cast<std::size_t>(m), 0);
  r.pair.resize(static_cast<std::size_t>(m));
  for (int j = 0; j < m; ++j) r.pair[static_cast<std::size_t>(j)] = j;
  r.n_pairs = m;
  // Contact rows without strength (the bond rule's normal rows with s_n = 0), the same in every
  // state: the cell has no bonds to break.
  const bond::Bounds intact = bond::bounds(bond::Kind::normal, bond::State::intact, 0, 0, 0);
  const bond::Bounds broken = bond::bounds(bond::Kind::normal, bond::State::broken, 0, 0, 0);
  r.lower_bonded = Eigen::VectorXd::Constant(m, intact.lower);
  r.upper_bonded = Eigen::VectorXd::Constant(m, intact.upper);
  r.lower_broken = Eigen::VectorXd::Constant(m, broken.lower);
  r.upper_broken = Eigen::VectorXd::Constant(m, broken.upper);
  r.bonded.assign(static_cast<std::size_t>(m), 0);
  return r;
}

Eigen::MatrixXd with_basis_compliance(Eigen::MatrixXd VtHV) {
  // More columns than the span of the cell's solutions has dimensions (the cone of solutions
  // needs more generators than its span), so H_r is singular on V's kernel, where Vμ = 0 and
  // nothing physical moves. A compliance δ per row makes it definite: each row softer by δ, so
  // the reduced cell stays on the soft side of the cell.
  if (VtHV.cols() > 0) VtHV.diagonal().array() += basis_compliance * VtHV.diagonal().maxCoeff();
  return VtHV;
}

CondensedCell cell_on_basis(const CondensedCell& cell, const Eigen::MatrixXd& V) {
  const Eigen::MatrixXd HV = cell.H * V;
  return cell_of_rows(cell, V.transpose() * cell.Y, with_basis_compliance(V.transpose() * HV));
}

ReducedCell reduce_cell(const CondensedCell& cell, const CellSample& training, const ReduceOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  ReducedCell out;
  const auto finish = [&](bool ok, std::string message) {
    out.ok = ok;
    out.message = std::move(message);
    out.seconds = seconds_since(start);
    return out;
  };
  if (cell.adhesion())
    return finish(false,
                  "the cell has adhesion: its bonded rows carry tension, which nonnegative combinations of "
                  "its solutions cannot represent");
  const int n = cell.n_rows();
  Eigen::MatrixXd V(n, 0);
  const std::vector<std::vector<int>> bodies =
      options.split_by_body ? bodies_of(cell) : std::vector<std::vector<int>>{[&] {
        std::vector<int> all(static_cast<std::size_t>(n));
        for (int i = 0; i < n; ++i) all[static_cast<std::size_t>(i)] = i;
        return all;
      }()};
  out.cell = cell_on_basis(cell, V);
  std::vector<double> error = check_reduced(out.cell, training).error;
  const auto worst_of = [&] {
    double worst = 0;
    for (double e : error)
      if (!std::isnan(e)) worst = std::max(worst, e);
    return worst;
  };
  out.training_max_error.push_back(worst_of());
  while (out.training_max_error.back() > options.tolerance) {
    if (V.cols() >= options.max_rows)
      return finish(false, "the training error is " + formatted("%.3g", out.training_max_error.back()) + " with " +
                               std::to_string(V.cols()) + " rows, above the tolerance " +
                               formatted("%.3g", options.tolerance) + " at the limit of rows");
    // The worst direction whose snapshot adds a new column.
    std::vector<std::size_t> order;
    for (std::size_t i = 0; i < error.size(); ++i)
      if (!std::isnan(error[i]) && error[i] > options.tolerance && training.forces[i].size() == n) order.push_back(i);
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return error[a] > error[b]; });
    bool added = false;
    for (std::size_t i : order) {
      // The snapshot's parts, body by body: each a column unless it repeats one.
      for (const std::vector<int>& body : bodies) {
        Eigen::VectorXd p = Eigen::VectorXd::Zero(n);
        for (int r : body) p(r) = training.forces[i](r);
        const double norm = p.norm();
        if (norm == 0) continue;
        bool repeated = false;  // a column already (to round-off)
        for (Eigen::Index j = 0; j < V.cols() && !repeated; ++j)
          repeated = (p / norm - V.col(j) / V.col(j).norm()).norm() <= repeat_floor;
        if (repeated || V.cols() >= options.max_rows) continue;
        V.conservativeResize(Eigen::NoChange, V.cols() + 1);
        V.col(V.cols() - 1) = p / p.cwiseAbs().maxCoeff();
        out.directions.push_back(training.direction[i]);
        added = true;
      }
      if (added) break;
    }
    if (!added)
      return finish(false, "no training direction above the tolerance adds a new solution (error " +
                               formatted("%.3g", out.training_max_error.back()) + ")");
    out.cell = cell_on_basis(cell, V);
    out.basis = V;
    error = check_reduced(out.cell, training).error;
    out.training_max_error.push_back(worst_of());
  }
  return finish(true, "");
}

ConeCheck check_reduced(const CondensedCell& reduced, const CellSample& sample) {
  CellEvaluator evaluator(reduced);
  CellHistory history = evaluator.unloaded();
  return check_law(
      [&](const Eigen::Vector3d& e) {
        const CellResponse r = evaluator.at_strain(e, history, BondMode::held);
        return r.ok ? r.stress : Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
      },
      sample);
}

}  // namespace dualcell::law
