#pragma once
// The independent check of a mesher's point identity (mesh::Mesh::point_of, point_sides,
// periodic_pairs) against what the coordinates say, for the mapped and the RVE mesher's tests.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>

#include "mesh/mesh.hpp"

namespace dualcell::testing {

// Matrix nodes share a point exactly when they are at one place (within tol), a fibre node is a
// point of its own; a point lies on the sides its coordinates say; the periodic pairs are every
// right (top) point with the point of its material one period back; mesh::point_problem agrees.
inline void expect_points_match_coordinates(const mesh::Mesh& m, double tol) {
  ASSERT_EQ(m.point_of.size(), m.nodes.size());
  const std::vector<char> on_fibre = mesh::fibre_nodes(m);
  const double W = m.block_width(), H = m.block_height();
  const auto place = [&](const Eigen::Vector2d& x) {
    return std::pair{std::llround(x.x() / tol), std::llround(x.y() / tol)};
  };
  // Per place and material, the points there (a fibre place: one per fibre node).
  std::map<std::tuple<long long, long long, char>, std::set<int>> points_at;
  std::map<std::tuple<long long, long long, char>, int> nodes_at;
  for (int v = 0; v < m.n_nodes(); ++v) {
    const auto [x, y] = place(m.nodes[v]);
    points_at[{x, y, on_fibre[v]}].insert(m.point_of[v]);
    ++nodes_at[{x, y, on_fibre[v]}];
    const Eigen::Vector2d& p = m.nodes[v];
    const int sides = (std::abs(p.x()) < tol) << mesh::left | (std::abs(p.x() - W) < tol) << mesh::right |
                      (std::abs(p.y()) < tol) << mesh::bottom | (std::abs(p.y() - H) < tol) << mesh::top;
    EXPECT_EQ(m.point_sides[m.point_of[v]], sides) << "node " << v;
  }
  std::set<int> seen;
  for (const auto& [at, points] : points_at) {
    const bool fibre = std::get<2>(at);
    EXPECT_EQ(points.size(), fibre ? std::size_t(nodes_at[at]) : 1u);
    for (int p : points) EXPECT_TRUE(seen.insert(p).second) << "point " << p << " at two places";
  }
  EXPECT_EQ(seen.size(), std::size_t(m.n_points()));
  // The pairs: right (top) points, one each, with the point one period back, same material.
  const std::vector<int> node = mesh::point_nodes(m);
  std::map<std::pair<int, int>, int> pairs;  // (point, side) -> partner
  for (const auto& [p, q, side] : m.periodic_pairs) {
    const Eigen::Vector2d back =
        m.nodes[node[p]] - (side == mesh::right ? Eigen::Vector2d(W, 0) : Eigen::Vector2d(0, H));
    EXPECT_LT((back - m.nodes[node[q]]).norm(), tol) << "pair " << p << " " << q;
    EXPECT_EQ(on_fibre[node[p]], on_fibre[node[q]]);
    EXPECT_TRUE(pairs.emplace(std::pair{p, int(side)}, q).second);
  }
  for (int p = 0; p < m.n_points(); ++p)
    for (const mesh::Side side : {mesh::right, mesh::top})
      EXPECT_EQ(pairs.count({p, int(side)}), (m.point_sides[p] & mesh::side_bit(side)) ? 1u : 0u) << p;
  EXPECT_EQ(mesh::point_problem(m), "");
}

}  // namespace dualcell::testing
