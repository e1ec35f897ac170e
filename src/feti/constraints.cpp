#include "feti/constraints.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "core/error.hpp"
#include "core/text.hpp"
#include "fem/assembly.hpp"
#include "fem/edge_conditions.hpp"
#include "law/bond.hpp"

namespace dualcell::feti {

const char* to_string(RowKind kind) {
  switch (kind) {
    case RowKind::glue:
      return "glue";
    case RowKind::dirichlet:
      return "dirichlet";
    case RowKind::periodic:
      return "periodic";
    case RowKind::normal:
      return "normal";
    case RowKind::tangential:
      return "tangential";
  }
  return "?";
}

BondState intact_bonds(const mesh::Mesh& mesh, const Interface& interface) {
  return BondState(mesh.interface_pairs.size(), interface.has_adhesion() ? 1 : 0);
}

Eigen::Vector2d interface_normal(const mesh::Mesh& mesh, int p) {
  const Eigen::Vector2d& x = mesh.nodes[mesh.interface_pairs[p][0]];
  const int f = mesh.interface_fibre[p];
  return (x - mesh.fibre_centres[f]) / mesh.fibre_radii[f];
}

std::vector<double> interface_lengths(const mesh::Mesh& mesh) {
  // L_p = ∫ φ_p ds over the rim edges around pair p, on the fibre's side (the matrix edge runs
  // through the same nodes): half of the two neighbouring chords for p1; for p2 the weights of
  // the parabola through each edge's three nodes (about 1/6, 4/6, 1/6 of its length).
  std::vector<double> length(mesh.interface_pairs.size(), 0.0);
  for (const mesh::RimEdge& e : mesh::interface_edges(mesh)) {
    const int pairs[3] = {e.pairs.a, e.pairs.b, e.pairs.mid}, nodes[3] = {e.nodes.a, e.nodes.b, e.nodes.mid};
    const int n = e.pairs.mid >= 0 ? 3 : 2;
    std::vector<Eigen::Vector2d> x;
    for (int i = 0; i < n; ++i) x.push_back(mesh.nodes[nodes[i]]);
    const std::array<double, 3> w = fem::edge_weights(x);
    for (int i = 0; i < n; ++i) length[pairs[i]] += w[i];
  }
  return length;
}

namespace {

// The nodes that carry the rows of the points of a side, in order along it (mesh::side_points).
std::vector<int> side_nodes(const mesh::Mesh& mesh, int side, const std::vector<int>& point_node) {
  std::vector<int> nodes;
  for (int p : mesh::side_points(mesh, side)) nodes.push_back(point_node[p]);
  return nodes;
}

}  // namespace

const std::array<int, 4> edge_sides = {mesh::left, mesh::right, mesh::bottom, mesh::top};

int node_at(const mesh::Mesh& mesh, const Eigen::Vector2d& x, const std::string& where, const char* what) {
  const int v = fem::node_near(
      mesh.n_nodes(), [&](int i) { return mesh.nodes[i]; }, x, std::max(mesh.block_width(), mesh.block_height()));
  if (v < 0) throw InputError(position_text(where, what, x) + ": no node of the mesh there");
  return v;
}

void check_positions(const mesh::Mesh& mesh, const EdgeLoads& loads) {
  for (const Support& support : loads.supports) node_at(mesh, support.at, support.where, "support");
  for (const PointLoad& p : loads.point_loads) node_at(mesh, p.at, p.where, "point load");
  node_at(mesh, loads.watch, loads.watch_where, "[output] watch");
}

namespace {

class RowBuilder {
 public:
  RowBuilder(Constraints& out, std::vector<Eigen::Triplet<double>>& triplets) : out_(out), triplets_(triplets) {}
  // Adds a row with entries (dof, value), unscaled bounds and weight w.
  void add(RowKind kind, int pair, std::initializer_list<std::pair<int, double>> entries, double lower, double upper,
           double w, double c = 0) {
    const int r = static_cast<int>(out_.kind.size());
    for (const auto& [dof, value] : entries)
      if (value != 0) triplets_.emplace_back(r, dof, w * value);
    out_.kind.push_back(kind);
    out_.pair.push_back(pair);
    lower_.push_back(lower / w);
    upper_.push_back(upper / w);
    weight_.push_back(w);
    c_.push_back(w * c);
  }
  void finish(int n_dofs) {
    const int n = static_cast<int>(out_.kind.size());
    out_.B.resize(n, n_dofs);
    out_.B.setFromTriplets(triplets_.begin(), triplets_.end());
    out_.c = Eigen::Map<Eigen::VectorXd>(c_.data(), n);
    out_.lower = Eigen::Map<Eigen::VectorXd>(lower_.data(), n);
    out_.upper = Eigen::Map<Eigen::VectorXd>(upper_.data(), n);
    out_.weight = Eigen::Map<Eigen::VectorXd>(weight_.data(), n);
  }

 private:
  Constraints& out_;
  std::vector<Eigen::Triplet<double>>& triplets_;
  std::vector<double> lower_, upper_, weight_, c_;
};

constexpr double unbounded = std::numeric_limits<double>::infinity();

// The periodic boundary (docs/method.md §12): u(x + Δx) − u(x) = H Δx with
// H = [[εxx, γ/2], [γ/2, εyy]] (symmetric: no rigid rotation), the macro DOFs from `macro` on.
// Left–right for every pair of the mesh (mesh::Mesh::periodic_pairs); bottom–top for all but
// the top-right corner, already tied through the other three corners; then the block's
// translation held at one corner. A row between two fibre nodes (an RVE's fibre cut by the
// edges, its pieces) has the fibre's weight w_fibre_pair, any other the matrix's w_pair.
void add_periodic_rows(RowBuilder& rows, const mesh::Mesh& mesh, const std::vector<int>& point_node,
                       const std::vector<int>& bottom_nodes, const std::vector<char>& on_fibre, int macro,
                       double w_pair, double w_fibre_pair, double w_single) {
  const auto weight = [&](int a, int b) { return on_fibre[a] && on_fibre[b] ? w_fibre_pair : w_pair; };
  const double inf = unbounded;
  const double Lx = mesh.block_width(), Ly = mesh.block_height();
  for (const mesh::PeriodicPair& pair : mesh.periodic_pairs) {
    if (pair.side != mesh::right) continue;
    const int l = point_node[pair.partner], r = point_node[pair.point];
    rows.add(RowKind::periodic, -1, {{2 * r, 1.0}, {2 * l, -1.0}, {macro + 0, -Lx}}, -inf, inf, weight(l, r));
    rows.add(RowKind::periodic, -1, {{2 * r + 1, 1.0}, {2 * l + 1, -1.0}, {macro + 2, -Lx / 2}}, -inf, inf,
             weight(l, r));
  }
  for (const mesh::PeriodicPair& pair : mesh.periodic_pairs) {
    if (pair.side != mesh::top || (mesh.point_sides[pair.point] & mesh::side_bit(mesh::right))) continue;
    const int b = point_node[pair.partner], t = point_node[pair.point];
    rows.add(RowKind::periodic, -1, {{2 * t, 1.0}, {2 * b, -1.0}, {macro + 2, -Ly / 2}}, -inf, inf, weight(b, t));
    rows.add(RowKind::periodic, -1, {{2 * t + 1, 1.0}, {2 * b + 1, -1.0}, {macro + 1, -Ly}}, -inf, inf, weight(b, t));
  }
  const int a = bottom_nodes.front();
  rows.add(RowKind::dirichlet, -1, {{2 * a, 1.0}}, -inf, inf, w_single);
  rows.add(RowKind::dirichlet, -1, {{2 * a + 1, 1.0}}, -inf, inf, w_single);
}

}  // namespace

std::vector<int> ties_at_strength(const Eigen::VectorXd& pair_forces, const std::vector<char>& bonded,
                                  const std::vector<double>& strength) {
  std::vector<int> out;
  for (std::size_t p = 0; p < bonded.size(); ++p)
    if (bonded[p] &&
        law::bond::at_strength(pair_forces(static_cast<Eigen::Index>(p)), law::bond::intact_along_fibres(strength[p])))
      out.push_back(static_cast<int>(p));
  return out;
}

primal::ShearResponse longitudinal_shear_cascade(const mesh::Mesh& mesh, const Scene& scene, std::vector<char>& bonded,
                                                 const Eigen::Vector2d& gamma, const std::vector<double>& strength) {
  primal::ShearResponse r;
  // Each round breaks at least one tie: one more solve than pairs ends every cascade.
  law::bond::cascade(
      bonded, static_cast<int>(bonded.size()) + 1,
      [&] {
        r = primal::longitudinal_shear_at(mesh, scene.fibre, scene.matrix, bonded, gamma, strength);
        return true;
      },
      [&](std::vector<int>& breaking) { breaking = ties_at_strength(r.pair_forces, bonded, strength); },
      [](const std::vector<int>&) {});
  return r;
}

std::vector<double> shear_strengths(const mesh::Mesh& mesh, const Scene& scene) {
  namespace bond = law::bond;
  const std::vector<double> length = interface_lengths(mesh);
  const double sn = scene.interface.normal_strength, st = scene.interface.tangential_strength;
  std::vector<double> strength(length.size());
  for (std::size_t p = 0; p < length.size(); ++p)
    strength[p] = bond::bounds(bond::Kind::along_fibres, bond::State::intact, sn, st, length[p]).upper;
  return strength;
}

namespace {

// Interface rows, pair by pair: normal, then tangential where the bond rule gives it a force to
// carry (bonded with shear strength): law::bond::bounds of the pair's state, with the strengths
// per unit length times the pair's length.
void add_interface_rows(RowBuilder& rows, const mesh::Mesh& mesh, const Scene& scene, const BondState& bonds,
                        double w_interface) {
  namespace bond = law::bond;
  const std::vector<double> length = interface_lengths(mesh);
  const double sn = scene.interface.normal_strength, st = scene.interface.tangential_strength;
  for (int p = 0; p < static_cast<int>(mesh.interface_pairs.size()); ++p) {
    const auto [f, m] = mesh.interface_pairs[p];
    const Eigen::Vector2d n = interface_normal(mesh, p), t(-n.y(), n.x());
    const bond::State state = bonds[p] != 0 ? bond::State::intact : bond::State::broken;
    const bond::Bounds normal = bond::bounds(bond::Kind::normal, state, sn, st, length[p]);
    const bond::Bounds tangential = bond::bounds(bond::Kind::tangential, state, sn, st, length[p]);
    rows.add(RowKind::normal, p, {{2 * f, n.x()}, {2 * f + 1, n.y()}, {2 * m, -n.x()}, {2 * m + 1, -n.y()}},
             normal.lower, normal.upper, w_interface);
    if (tangential.carries_force())
      rows.add(RowKind::tangential, p, {{2 * f, t.x()}, {2 * f + 1, t.y()}, {2 * m, -t.x()}, {2 * m + 1, -t.y()}},
               tangential.lower, tangential.upper, w_interface);
  }
}

}  // namespace

Constraints build_constraints(const mesh::Mesh& mesh, const Scene& scene, const BondState& bonds) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  Constraints out;
  std::vector<Eigen::Triplet<double>> triplets;
  RowBuilder rows(out, triplets);
  const int dim_u = mesh.dim_u();
  const bool periodic = scene.load.boundary == Boundary::periodic;
  out.n_macro_dofs = periodic ? 3 : 0;
  const int macro = dim_u;  // first macro DOF: εxx, εyy, γxy

  // Row scaling: w² = (1/E_m) / Σ 1/E_i over the subdomains a row couples (see header).
  const double Em = scene.matrix.E, Ef = scene.fibre.E;
  const double w_matrix_pair = std::sqrt(0.5);
  const double w_fibre_pair = std::sqrt((1 / Em) / (2 / Ef));
  const double w_single = 1.0;
  const double w_interface = std::sqrt((1 / Em) / (1 / Em + 1 / Ef));

  for (int q = 0; q < static_cast<int>(mesh.glue_pairs.size()); ++q) {
    const auto [a, b] = mesh.glue_pairs[q];
    for (int c = 0; c < 2; ++c)
      rows.add(RowKind::glue, q, {{2 * a + c, 1.0}, {2 * b + c, -1.0}}, -inf, inf, w_matrix_pair);
  }

  const std::vector<int> point_node = mesh::point_nodes(mesh);
  const std::vector<char> on_fibre = mesh::fibre_nodes(mesh);
  const std::vector<int> bottom_nodes = side_nodes(mesh, mesh::bottom, point_node);
  switch (scene.load.boundary) {
    case Boundary::symmetry: {
      // u_x = 0 on x = 0 and u_y = 0 on y = 0 (the `symmetry` boundary, docs/method.md §12), once per physical point:
      // the other copies follow through their glue rows.
      for (int v : side_nodes(mesh, mesh::left, point_node))
        rows.add(RowKind::dirichlet, -1, {{2 * v, 1.0}}, -inf, inf, w_single);
      for (int v : bottom_nodes) rows.add(RowKind::dirichlet, -1, {{2 * v + 1, 1.0}}, -inf, inf, w_single);
      break;
    }
    case Boundary::traction: {
      // The minimal set that removes the rigid motion: both components at the lower left
      // corner, the vertical one at the lower right corner.
      const int a = bottom_nodes.front(), b = bottom_nodes.back();
      rows.add(RowKind::dirichlet, -1, {{2 * a, 1.0}}, -inf, inf, w_single);
      rows.add(RowKind::dirichlet, -1, {{2 * a + 1, 1.0}}, -inf, inf, w_single);
      rows.add(RowKind::dirichlet, -1, {{2 * b + 1, 1.0}}, -inf, inf, w_single);
      break;
    }
    case Boundary::periodic:
      add_periodic_rows(rows, mesh, point_node, bottom_nodes, on_fibre, macro, w_matrix_pair, w_fibre_pair, w_single);
      break;
    case Boundary::edges: {
      // Per edge (core/edge_loads.hpp), once per physical point and component: a point held by
      // two edges (a corner) or a support as well keeps the first row only, so that B has full
      // row rank. c holds the prescribed displacements at load factor 1.
      const EdgeLoads& loads = scene.load.edge_loads;
      std::array<std::vector<int>, 4> edge_points;
      for (int e = 0; e < 4; ++e) edge_points[e] = side_nodes(mesh, edge_sides[e], point_node);
      const auto held = fem::held_components(loads, edge_points, [&](const Support& support) {
        return point_node[mesh.point_of[node_at(mesh, support.at, support.where, "support")]];
      });
      for (const fem::HeldComponent& h : held)
        rows.add(RowKind::dirichlet, -1, {{2 * h.point + h.component, 1.0}}, -inf, inf, w_single, h.value);
      break;
    }
  }

  add_interface_rows(rows, mesh, scene, bonds, w_interface);
  rows.finish(dim_u + out.n_macro_dofs);
  return out;
}

}  // namespace dualcell::feti
