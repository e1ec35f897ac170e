#pragma once
// Edge conditions, supports and edge tractions on node coordinates, for every solver that applies
// core/edge_loads.hpp: the dual solver's Dirichlet rows (feti/constraints.cpp), the one-body
// reference (primal/one_body.cpp) and the structure of homogeneous cells (structure.cpp). It
// knows nothing of cells or fibres: points are the caller's numbers (a node, a class of
// coinciding nodes, a merged node), so any mesher's nodes can use it.
#include <Eigen/Core>
#include <array>
#include <functional>
#include <span>
#include <vector>

#include "core/edge_loads.hpp"

namespace dualcell::fem {

// "The node at a position" the user gives (a support, a point load, a watch point) is found by
// the one tolerance rule, node_reach (core/edge_loads.hpp). Sides and periodic partners are not
// found by position: the mesh records them (mesh::Mesh::point_sides, periodic_pairs; its meshers
// and reader use the same rule, mesh::side_tolerance).

// The first of n points, position(i), within node_reach(body_size) of x; −1 when none is.
template <typename Position>
int node_near(int n, Position position, const Eigen::Vector2d& x, double body_size) {
  const double reach = node_reach(body_size);
  for (int i = 0; i < n; ++i)
    if ((position(i) - x).norm() <= reach) return i;
  return -1;
}

// A displacement component held by an edge condition or a support: the point, x (0) or y (1),
// its value at load factor 1, and what holds it (the edge, 0..3 in the order of edge_names, or
// held_by_support).
struct HeldComponent {
  int point = -1, component = 0;
  double value = 0;
  int by = 0;
};
inline constexpr int held_by_support = 4;

// Every component that the edge conditions (fixed: both; roller: the normal one; displacement:
// the prescribed ones) and the supports of `loads` hold, once per (point, component), the first
// condition winning, in this order: the edges left, right, bottom, top, each along
// `edge_points[e]`, then the supports, each at support_point(support). A corner held by two
// edges thus keeps the first edge's value, and a point a support holds again adds nothing.
std::vector<HeldComponent> held_components(const EdgeLoads& loads, const std::array<std::vector<int>, 4>& edge_points,
                                           const std::function<int(const Support&)>& support_point);

// Consistent nodal forces ∫ φ_i t ds of a traction linear in the edge parameter, t_a at the
// first node and t_b at the second, over one edge element with node positions x (2 nodes, or 3:
// ends, then middle, on a parabola) and node numbers `nodes`, added to f at 2·node + c.
void add_edge_traction(std::span<const Eigen::Vector2d> x, std::span<const int> nodes, const Eigen::Vector2d& t_a,
                       const Eigen::Vector2d& t_b, Eigen::VectorXd& f);

}  // namespace dualcell::fem
