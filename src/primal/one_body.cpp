#include "primal/one_body.hpp"

#include <Eigen/SparseCore>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <map>
#include <numeric>
#include <vector>

#include "core/error.hpp"
#include "fem/assembly.hpp"
#include "fem/edge_conditions.hpp"
#include "linalg/sparse_cholesky.hpp"

namespace dualcell::primal {

Eigen::VectorXd solve_one_body(const mesh::Mesh& m, const Scene& scene, const Eigen::VectorXd& f, bool holes,
                               bool refine, double* seconds_factorise_solve, double load_factor) {
  const int N = m.n_nodes();
  std::vector<int> parent(N);
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  for (const auto& [a, b] : m.glue_pairs) parent[find(a)] = find(b);
  if (!holes)
    for (const auto& [a, b] : m.interface_pairs) parent[find(a)] = find(b);
  std::vector<bool> absent(N, false);
  if (holes)
    for (const auto& sub : m.subdomains)
      if (sub.is_fibre)
        for (int v = sub.node_begin; v < sub.node_end; ++v) absent[v] = true;

  const bool periodic = scene.load.boundary == Boundary::periodic;
  const double W = m.block_width(), H = m.block_height();
  const double tol = 1e-12 * (W + H);
  // Physical points on the outer boundary by position.
  auto on = [&](int v, int side) {
    const auto& x = m.nodes[v];
    switch (side) {
      case mesh::left:
        return std::abs(x.x()) < tol;
      case mesh::right:
        return std::abs(x.x() - W) < tol;
      case mesh::bottom:
        return std::abs(x.y()) < tol;
      default:
        return std::abs(x.y() - H) < tol;
    }
  };
  // Slave map for periodic: root → (master root, H-coefficients of the jump per component).
  std::map<int, std::pair<int, Eigen::Matrix<double, 2, 3>>> slave;
  if (periodic) {
    std::map<std::pair<long, long>, int> at;  // rounded position → root
    auto key = [&](const Eigen::Vector2d& x) {
      return std::pair<long, long>(std::lround(x.x() * 1e9), std::lround(x.y() * 1e9));
    };
    for (int v = 0; v < N; ++v) at[key(m.nodes[v])] = find(v);
    for (int v = 0; v < N; ++v) {
      const int root = find(v);
      if (slave.count(root)) continue;
      Eigen::Matrix<double, 2, 3> J = Eigen::Matrix<double, 2, 3>::Zero();
      // u_right = u_left + H(W, 0): x: W εxx, y: W γ/2. u_top = u_bottom + H(0, H): x: H γ/2, y: H εyy.
      if (on(v, mesh::right)) {
        J << W, 0, 0, 0, 0, W / 2;
        slave[root] = {at[key(m.nodes[v] - Eigen::Vector2d(W, 0))], J};
      } else if (on(v, mesh::top)) {
        J << 0, 0, H / 2, 0, H, 0;
        slave[root] = {at[key(m.nodes[v] - Eigen::Vector2d(0, H))], J};
      }
    }
  }
  // Dirichlet DOFs (per root and component) and their values.
  std::map<std::pair<int, int>, double> fixed;
  // The (merged) node at a corner or support; a position off the mesh is an input error, never
  // a silent −1.
  auto corner = [&](double x, double y) {
    const int v = fem::node_near(
        N, [&](int i) { return m.nodes[i]; }, Eigen::Vector2d(x, y), std::max(W, H));
    if (v < 0) throw InputError(position_text("", "support", Eigen::Vector2d(x, y)) + ": no node of the mesh there");
    return find(v);
  };
  switch (scene.load.boundary) {
    case Boundary::symmetry:
      for (int v = 0; v < N; ++v) {
        if (on(v, mesh::left)) fixed[{find(v), 0}] = 0.0;
        if (on(v, mesh::bottom)) fixed[{find(v), 1}] = 0.0;
      }
      break;
    case Boundary::traction:
      fixed[{corner(0, 0), 0}] = fixed[{corner(0, 0), 1}] = fixed[{corner(W, 0), 1}] = 0.0;
      break;
    case Boundary::periodic:
      fixed[{corner(0, 0), 0}] = fixed[{corner(0, 0), 1}] = 0.0;
      break;
    case Boundary::edges: {
      // The merged nodes on each side, and the conditions on them as the dual solver's rows
      // have them (fem::held_components: the first condition wins at a point held twice).
      const int sides[4] = {mesh::left, mesh::right, mesh::bottom, mesh::top};
      std::array<std::vector<int>, 4> edge_points;
      for (int e = 0; e < 4; ++e)
        for (int v = 0; v < N; ++v)
          if (!absent[v] && on(v, sides[e])) edge_points[e].push_back(find(v));
      const auto held = fem::held_components(scene.load.edge_loads, edge_points,
                                             [&](const Support& s) { return corner(s.at.x(), s.at.y()); });
      for (const fem::HeldComponent& h : held) fixed.insert({{h.point, h.component}, load_factor * h.value});
      break;
    }
  }
  // Reduced numbering.
  std::map<std::pair<int, int>, int> index;
  int n = 0;
  for (int v = 0; v < N; ++v) {
    const int root = find(v);
    if (slave.count(root) || absent[v]) continue;
    for (int c = 0; c < 2; ++c)
      if (!fixed.count({root, c}) && !index.count({root, c})) index[{root, c}] = n++;
  }
  const int macro = n;
  if (periodic) n += 3;
  const int dim = m.dim_u() + (periodic ? 3 : 0);
  std::vector<Eigen::Triplet<double>> t;
  for (int v = 0; v < N; ++v)
    for (int c = 0; c < 2; ++c) {
      if (absent[v]) continue;
      int root = find(v);
      Eigen::RowVector3d jump = Eigen::RowVector3d::Zero();
      while (slave.count(root)) {
        jump += slave[root].second.row(c);
        root = slave[root].first;
      }
      if (!fixed.count({root, c})) t.emplace_back(2 * v + c, index.at({root, c}), 1.0);
      for (int k = 0; k < 3; ++k)
        if (jump(k) != 0) t.emplace_back(2 * v + c, macro + k, jump(k));
    }
  if (periodic)
    for (int k = 0; k < 3; ++k) t.emplace_back(m.dim_u() + k, macro + k, 1.0);
  Eigen::SparseMatrix<double> T(dim, n);
  T.setFromTriplets(t.begin(), t.end());
  // K over all DOFs (block diagonal of the subdomains; the macro DOFs carry no stiffness).
  std::vector<Eigen::Triplet<double>> kt;
  for (int s = 0; s < static_cast<int>(m.subdomains.size()); ++s) {
    if (holes && m.subdomains[s].is_fibre) continue;
    const auto K = fem::assemble_stiffness(m, s, m.subdomains[s].is_fibre ? scene.fibre : scene.matrix);
    const int offset = 2 * m.subdomains[s].node_begin;
    for (int k = 0; k < K.outerSize(); ++k)
      for (Eigen::SparseMatrix<double>::InnerIterator it(K, k); it; ++it)
        kt.emplace_back(offset + it.row(), offset + it.col(), it.value());
  }
  Eigen::SparseMatrix<double> K(dim, dim);
  K.setFromTriplets(kt.begin(), kt.end());
  const Eigen::SparseMatrix<double> K_red = Eigen::SparseMatrix<double>(T.transpose() * K * T);
  // Prescribed values on every copy of a held point: u = T z + u_D, K_red z = Tᵀ(f − K u_D).
  Eigen::VectorXd u_D = Eigen::VectorXd::Zero(dim);
  for (int v = 0; v < N; ++v)
    for (int c = 0; c < 2; ++c)
      if (const auto it = fixed.find({find(v), c}); it != fixed.end() && !absent[v]) u_D(2 * v + c) = it->second;
  const Eigen::VectorXd f_red = T.transpose() * (f - K * u_D);
  const auto t0 = std::chrono::steady_clock::now();
  linalg::SparseCholesky cholesky;
  cholesky.compute(K_red);
  // Iterative refinement with the residual in long double: with stiffness contrasts up to 1e6,
  // κ(K_red) reaches ~1e10 and one Cholesky solve is accurate to only ~κ·eps relative; the
  // refined solution is accurate to working precision, so the oracle is not the weak side.
  Eigen::VectorXd z, dz, r(n);
  cholesky.solve(f_red, z);
  if (seconds_factorise_solve)
    *seconds_factorise_solve = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  for (int sweep = 0; refine && sweep < 3; ++sweep) {
    for (int i = 0; i < n; ++i) r(i) = 0;
    std::vector<long double> acc(n, 0.0L);
    for (int k = 0; k < K_red.outerSize(); ++k)
      for (Eigen::SparseMatrix<double>::InnerIterator it(K_red, k); it; ++it)
        acc[it.row()] += static_cast<long double>(it.value()) * static_cast<long double>(z(it.col()));
    for (int i = 0; i < n; ++i) r(i) = static_cast<double>(static_cast<long double>(f_red(i)) - acc[i]);
    cholesky.solve(r, dz);
    z += dz;
  }
  return T * z + u_D;
}

}  // namespace dualcell::primal
