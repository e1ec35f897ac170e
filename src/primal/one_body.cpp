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

namespace {

// The block as one body: every node's root (glued copies merged; with `holes` the fibres are
// absent, otherwise their interface nodes merge with the matrix's), by union–find.
struct Points {
  std::vector<int> parent;
  std::vector<bool> absent;  // fibre nodes left out (holes)
  int find(int v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  }
};

Points merge_points(const mesh::Mesh& m, bool holes) {
  const int N = m.n_nodes();
  Points p;
  p.parent.resize(N);
  std::iota(p.parent.begin(), p.parent.end(), 0);
  for (const auto& [a, b] : m.glue_pairs) p.parent[p.find(a)] = p.find(b);
  if (!holes)
    for (const auto& [a, b] : m.interface_pairs) p.parent[p.find(a)] = p.find(b);
  p.absent.assign(N, false);
  if (holes)
    for (const auto& sub : m.subdomains)
      if (sub.is_fibre)
        for (int v = sub.node_begin; v < sub.node_end; ++v) p.absent[v] = true;
  return p;
}

// Whether node v lies on a side of the block (physical points by position).
bool on_side(const mesh::Mesh& m, int v, int side) {
  const double W = m.block_width(), H = m.block_height(), tol = 1e-12 * (W + H);
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
}

// Periodic: root of a right or top point → (its master's root on the opposite side, the
// coefficients of the jump H·(W, 0) or H·(0, H) on the macro DOFs (εxx, εyy, γxy) per component).
using Slaves = std::map<int, std::pair<int, Eigen::Matrix<double, 2, 3>>>;
Slaves periodic_slaves(const mesh::Mesh& m, Points& p) {
  const int N = m.n_nodes();
  const double W = m.block_width(), H = m.block_height();
  Slaves slave;
  std::map<std::pair<long, long>, int> at;  // rounded position → root
  auto key = [&](const Eigen::Vector2d& x) {
    return std::pair<long, long>(std::lround(x.x() * 1e9), std::lround(x.y() * 1e9));
  };
  for (int v = 0; v < N; ++v) at[key(m.nodes[v])] = p.find(v);
  for (int v = 0; v < N; ++v) {
    const int root = p.find(v);
    if (slave.count(root)) continue;
    Eigen::Matrix<double, 2, 3> J = Eigen::Matrix<double, 2, 3>::Zero();
    // u_right = u_left + H(W, 0): x: W εxx, y: W γ/2. u_top = u_bottom + H(0, H): x: H γ/2, y: H εyy.
    if (on_side(m, v, mesh::right)) {
      J << W, 0, 0, 0, 0, W / 2;
      slave[root] = {at[key(m.nodes[v] - Eigen::Vector2d(W, 0))], J};
    } else if (on_side(m, v, mesh::top)) {
      J << 0, 0, H / 2, 0, H, 0;
      slave[root] = {at[key(m.nodes[v] - Eigen::Vector2d(0, H))], J};
    }
  }
  return slave;
}

// The Dirichlet DOFs (root, component) of the boundary and their values.
std::map<std::pair<int, int>, double> held_dofs(const mesh::Mesh& m, const Scene& scene, Points& p,
                                                double load_factor) {
  const int N = m.n_nodes();
  const double W = m.block_width(), H = m.block_height();
  std::map<std::pair<int, int>, double> fixed;
  // The (merged) node at a corner or support; a position off the mesh is an input error, never
  // a silent −1.
  auto corner = [&](double x, double y) {
    const int v = fem::node_near(
        N, [&](int i) { return m.nodes[i]; }, Eigen::Vector2d(x, y), std::max(W, H));
    if (v < 0) throw InputError(position_text("", "support", Eigen::Vector2d(x, y)) + ": no node of the mesh there");
    return p.find(v);
  };
  switch (scene.load.boundary) {
    case Boundary::symmetry:
      for (int v = 0; v < N; ++v) {
        if (on_side(m, v, mesh::left)) fixed[{p.find(v), 0}] = 0.0;
        if (on_side(m, v, mesh::bottom)) fixed[{p.find(v), 1}] = 0.0;
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
          if (!p.absent[v] && on_side(m, v, sides[e])) edge_points[e].push_back(p.find(v));
      const auto held = fem::held_components(scene.load.edge_loads, edge_points,
                                             [&](const Support& s) { return corner(s.at.x(), s.at.y()); });
      for (const fem::HeldComponent& h : held) fixed.insert({{h.point, h.component}, load_factor * h.value});
      break;
    }
  }
  return fixed;
}

// K over all DOFs (block diagonal of the subdomains; the macro DOFs, `extra`, carry none).
Eigen::SparseMatrix<double> block_stiffness(const mesh::Mesh& m, const Scene& scene, bool holes, int extra) {
  std::vector<Eigen::Triplet<double>> kt;
  for (int s = 0; s < static_cast<int>(m.subdomains.size()); ++s) {
    if (holes && m.subdomains[s].is_fibre) continue;
    const auto K = fem::assemble_stiffness(m, s, m.subdomains[s].is_fibre ? scene.fibre : scene.matrix);
    const int offset = 2 * m.subdomains[s].node_begin;
    for (int k = 0; k < K.outerSize(); ++k)
      for (Eigen::SparseMatrix<double>::InnerIterator it(K, k); it; ++it)
        kt.emplace_back(offset + it.row(), offset + it.col(), it.value());
  }
  Eigen::SparseMatrix<double> K(m.dim_u() + extra, m.dim_u() + extra);
  K.setFromTriplets(kt.begin(), kt.end());
  return K;
}

// K_red z = f_red by CHOLMOD, then (with `refine`) three sweeps of iterative refinement with
// the residual in long double: with stiffness contrasts up to 1e6, κ(K_red) reaches ~1e10 and
// one Cholesky solve is accurate to only ~κ·eps relative; the refined solution is accurate to
// working precision, so the oracle is not the weak side.
Eigen::VectorXd solve_refined(const Eigen::SparseMatrix<double>& K_red, const Eigen::VectorXd& f_red, bool refine,
                              double* seconds_factorise_solve) {
  const Eigen::Index n = K_red.rows();
  const auto t0 = std::chrono::steady_clock::now();
  linalg::SparseCholesky cholesky;
  cholesky.compute(K_red);
  Eigen::VectorXd z, dz, r(n);
  cholesky.solve(f_red, z);
  if (seconds_factorise_solve)
    *seconds_factorise_solve = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  for (int sweep = 0; refine && sweep < 3; ++sweep) {
    std::vector<long double> acc(n, 0.0L);
    for (int k = 0; k < K_red.outerSize(); ++k)
      for (Eigen::SparseMatrix<double>::InnerIterator it(K_red, k); it; ++it)
        acc[it.row()] += static_cast<long double>(it.value()) * static_cast<long double>(z(it.col()));
    for (Eigen::Index i = 0; i < n; ++i) r(i) = static_cast<double>(static_cast<long double>(f_red(i)) - acc[i]);
    cholesky.solve(r, dz);
    z += dz;
  }
  return z;
}

}  // namespace

Eigen::VectorXd solve_one_body(const mesh::Mesh& m, const Scene& scene, const Eigen::VectorXd& f, bool holes,
                               bool refine, double* seconds_factorise_solve, double load_factor) {
  const int N = m.n_nodes();
  Points points = merge_points(m, holes);
  const bool periodic = scene.load.boundary == Boundary::periodic;
  Slaves slave = periodic ? periodic_slaves(m, points) : Slaves{};
  const std::map<std::pair<int, int>, double> fixed = held_dofs(m, scene, points, load_factor);
  // Reduced numbering: u = T z + u_D, z the free DOFs of the masters (and the macro DOFs).
  std::map<std::pair<int, int>, int> index;
  int n = 0;
  for (int v = 0; v < N; ++v) {
    const int root = points.find(v);
    if (slave.count(root) || points.absent[v]) continue;
    for (int c = 0; c < 2; ++c)
      if (!fixed.count({root, c}) && !index.count({root, c})) index[{root, c}] = n++;
  }
  const int macro = n;
  if (periodic) n += 3;
  const int dim = m.dim_u() + (periodic ? 3 : 0);
  std::vector<Eigen::Triplet<double>> t;
  for (int v = 0; v < N; ++v)
    for (int c = 0; c < 2; ++c) {
      if (points.absent[v]) continue;
      int root = points.find(v);
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
  const Eigen::SparseMatrix<double> K = block_stiffness(m, scene, holes, periodic ? 3 : 0);
  const Eigen::SparseMatrix<double> K_red = Eigen::SparseMatrix<double>(T.transpose() * K * T);
  // Prescribed values on every copy of a held point: K_red z = Tᵀ(f − K u_D).
  Eigen::VectorXd u_D = Eigen::VectorXd::Zero(dim);
  for (int v = 0; v < N; ++v)
    for (int c = 0; c < 2; ++c)
      if (const auto it = fixed.find({points.find(v), c}); it != fixed.end() && !points.absent[v])
        u_D(2 * v + c) = it->second;
  const Eigen::VectorXd f_red = T.transpose() * (f - K * u_D);
  return T * solve_refined(K_red, f_red, refine, seconds_factorise_solve) + u_D;
}

}  // namespace dualcell::primal
