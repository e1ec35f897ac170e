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
#include "core/progress.hpp"
#include "fem/assembly.hpp"
#include "fem/edge_conditions.hpp"
#include "linalg/sparse_cholesky.hpp"

namespace dualcell::primal {

namespace {

// The block as one body: its points are the mesh's physical points (glued copies are one
// already), a fibre's interface point merged into its matrix partner; with `holes` the fibres
// are absent instead.
struct Points {
  std::vector<int> body;      // per mesh point: its point of the body
  std::vector<int> of_node;   // per node: its point of the body
  std::vector<bool> absent;   // per node: a fibre node left out (holes)
  std::vector<bool> missing;  // per mesh point: the same
};

Points merge_points(const mesh::Mesh& m, bool holes) {
  Points p;
  p.body.resize(m.n_points());
  std::iota(p.body.begin(), p.body.end(), 0);
  if (!holes)
    for (const auto& [f, mn] : m.interface_pairs) p.body[m.point_of[f]] = m.point_of[mn];
  const std::vector<char> on_fibre = mesh::fibre_nodes(m);
  p.absent.assign(m.n_nodes(), false);
  p.missing.assign(m.n_points(), false);
  for (int v = 0; v < m.n_nodes(); ++v) {
    p.of_node.push_back(p.body[m.point_of[v]]);
    if (holes && on_fibre[v]) p.absent[v] = p.missing[m.point_of[v]] = true;
  }
  return p;
}

// Periodic: a right or top point of the body → (its partner's on the opposite side, the
// coefficients of the jump H·(W, 0) or H·(0, H) on the macro DOFs (εxx, εyy, γxy) per component).
// A top-right corner follows its right pair.
using Slaves = std::map<int, std::pair<int, Eigen::Matrix<double, 2, 3>>>;
Slaves periodic_slaves(const mesh::Mesh& m, const Points& p) {
  const double W = m.block_width(), H = m.block_height();
  Slaves slave;
  for (const mesh::Side side : {mesh::right, mesh::top})
    for (const mesh::PeriodicPair& pair : m.periodic_pairs) {
      if (pair.side != side || slave.count(p.body[pair.point])) continue;
      Eigen::Matrix<double, 2, 3> J = Eigen::Matrix<double, 2, 3>::Zero();
      // u_right = u_left + H(W, 0): x: W εxx, y: W γ/2. u_top = u_bottom + H(0, H): x: H γ/2, y: H εyy.
      if (side == mesh::right)
        J << W, 0, 0, 0, 0, W / 2;
      else
        J << 0, 0, H / 2, 0, H, 0;
      slave[p.body[pair.point]] = {p.body[pair.partner], J};
    }
  return slave;
}

// The points of the body on a side (those present), in order along it.
std::vector<int> side_points(const mesh::Mesh& m, const Points& p, int side) {
  std::vector<int> points;
  for (int q : mesh::side_points(m, side))
    if (!p.missing[q]) points.push_back(p.body[q]);
  return points;
}

// The Dirichlet DOFs (point of the body, component) of the boundary and their values.
std::map<std::pair<int, int>, double> held_dofs(const mesh::Mesh& m, const Scene& scene, const Points& p,
                                                double load_factor) {
  std::map<std::pair<int, int>, double> fixed;
  // The corners of the block: the ends of its bottom side.
  const std::vector<int> bottom = side_points(m, p, mesh::bottom);
  switch (scene.load.boundary) {
    case Boundary::symmetry:
      for (int q : side_points(m, p, mesh::left)) fixed[{q, 0}] = 0.0;
      for (int q : bottom) fixed[{q, 1}] = 0.0;
      break;
    case Boundary::traction:
      fixed[{bottom.front(), 0}] = fixed[{bottom.front(), 1}] = fixed[{bottom.back(), 1}] = 0.0;
      break;
    case Boundary::periodic:
      fixed[{bottom.front(), 0}] = fixed[{bottom.front(), 1}] = 0.0;
      break;
    case Boundary::edges: {
      // The points on each side, and the conditions on them as the dual solver's rows have them
      // (fem::held_components: the first condition wins at a point held twice). A support is at
      // a position the scene gives, off the mesh an input error, never a silent −1.
      const int sides[4] = {mesh::left, mesh::right, mesh::bottom, mesh::top};
      std::array<std::vector<int>, 4> edge_points;
      for (int e = 0; e < 4; ++e) edge_points[e] = side_points(m, p, sides[e]);
      const auto support_point = [&](const Support& s) {
        const int v = fem::node_near(
            m.n_nodes(), [&](int i) { return m.nodes[i]; }, s.at, std::max(m.block_width(), m.block_height()));
        if (v < 0) throw InputError(position_text("", "support", s.at) + ": no node of the mesh there");
        return p.of_node[v];
      };
      const auto held = fem::held_components(scene.load.edge_loads, edge_points, support_point);
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
  if (seconds_factorise_solve) *seconds_factorise_solve = seconds_since(t0);
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
  const Points points = merge_points(m, holes);
  const bool periodic = scene.load.boundary == Boundary::periodic;
  const Slaves slave = periodic ? periodic_slaves(m, points) : Slaves{};
  const std::map<std::pair<int, int>, double> fixed = held_dofs(m, scene, points, load_factor);
  // Reduced numbering: u = T z + u_D, z the free DOFs of the masters (and the macro DOFs).
  std::map<std::pair<int, int>, int> index;
  int n = 0;
  for (int v = 0; v < N; ++v) {
    const int root = points.of_node[v];
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
      int root = points.of_node[v];
      Eigen::RowVector3d jump = Eigen::RowVector3d::Zero();
      while (slave.count(root)) {
        jump += slave.at(root).second.row(c);
        root = slave.at(root).first;
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
      if (const auto it = fixed.find({points.of_node[v], c}); it != fixed.end() && !points.absent[v])
        u_D(2 * v + c) = it->second;
  const Eigen::VectorXd f_red = T.transpose() * (f - K * u_D);
  return T * solve_refined(K_red, f_red, refine, seconds_factorise_solve) + u_D;
}

}  // namespace dualcell::primal
