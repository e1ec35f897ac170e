#include "mesh/mesh.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <map>
#include <numbers>
#include <tuple>

#include "core/edge_loads.hpp"

namespace dualcell::mesh {

namespace {

// Position along the perimeter of the L∞ ring of level l through grid offset (di, dj),
// counted counter-clockwise from (l, 0) in units of grid steps: an integer in [0, 8l).
// Nodes on the fibre rim and on the matrix hole get the same integer, hence the same angle
// and bitwise identical coordinates.
int perimeter_position(int di, int dj, int l) {
  if (di == l && dj >= 0) return dj;
  if (dj == l) return l + (l - di);
  if (di == -l) return 3 * l + (l - dj);
  if (dj == -l) return 5 * l + (di + l);
  return 7 * l + (dj + l);  // di == l, dj < 0
}

double ring_angle(int di, int dj, int l) { return std::numbers::pi / 4 * perimeter_position(di, dj, l) / l; }

// Fibre ring radius as a fraction of r, pushed slightly towards the rim (docs/method.md §2):
// g(0) = 0, g(1) = 1, g'(1) = 0.8 so the outermost ring of elements is a little thinner.
double fibre_ring_radius(double x) { return x * (1.2 - 0.2 * x); }

// Appends the two triangles of the quad with corners q[0..3] (counter-clockwise), split along the
// shorter diagonal. For p2, mid[0..3] are the mid-side nodes of the quad edges (q0,q1), (q1,q2),
// (q2,q3), (q3,q0) and centre the node in the middle of the quad (on both diagonals).
void split_quad(const std::vector<Eigen::Vector2d>& nodes, const int q[4], const int* mid, int centre,
                Triangles& triangles) {
  const double ac = (nodes[q[0]] - nodes[q[2]]).squaredNorm();
  const double bd = (nodes[q[1]] - nodes[q[3]]).squaredNorm();
  if (ac <= bd) {
    if (mid) {
      triangles.push_back({q[0], q[1], q[2], mid[0], mid[1], centre});
      triangles.push_back({q[0], q[2], q[3], centre, mid[2], mid[3]});
    } else {
      triangles.push_back({q[0], q[1], q[2]});
      triangles.push_back({q[0], q[2], q[3]});
    }
  } else {
    if (mid) {
      triangles.push_back({q[0], q[1], q[3], mid[0], centre, mid[3]});
      triangles.push_back({q[1], q[2], q[3], mid[1], mid[2], centre});
    } else {
      triangles.push_back({q[0], q[1], q[3]});
      triangles.push_back({q[1], q[2], q[3]});
    }
  }
}

// Appends the triangles of the coarse quad whose lower-left fine grid index is (i, j), on a fine
// grid of row length `stride` with `o` fine steps per coarse step (1: p1, 2: p2).
//
// p2: a mid-side node keeps its mapped position only where that is on a curve or line the mesh
// must follow, the circle (rim and hole) or a cell edge (`keep`); every other one moves to the
// midpoint of its edge's corners. The map has a kink along the cell's diagonals (the square
// rings turn their corners there), and a mid-side node taken from the map across the kink sits
// up to 19 % of the edge length off the chord at every degree: an O(1) distortion that would
// cost the isoparametric element its order. Straight interior edges have none.
void add_quad(std::vector<Eigen::Vector2d>& nodes, const std::vector<char>& keep, const std::vector<int>& grid,
              int stride, int o, int i, int j, Triangles& triangles) {
  const auto at = [&](int di, int dj) { return grid[(i + di) + stride * (j + dj)]; };
  const int q[4] = {at(0, 0), at(o, 0), at(o, o), at(0, o)};
  if (o == 1) {
    split_quad(nodes, q, nullptr, -1, triangles);
    return;
  }
  const int mid[4] = {at(1, 0), at(2, 1), at(1, 2), at(0, 1)};
  split_quad(nodes, q, mid, at(1, 1), triangles);
  for (std::size_t t = triangles.size() - 2; t < triangles.size(); ++t) {
    const auto tri = triangles[t];
    for (int e = 0; e < 3; ++e)
      if (!keep[tri[3 + e]]) nodes[tri[3 + e]] = (nodes[tri[e]] + nodes[tri[(e + 1) % 3]]) / 2;
  }
}

}  // namespace

int matrix_nodes_per_cell(int degree, Element element) {
  const int k = degree * element_order(element);
  return (4 * k + 1) * (4 * k + 1) - (2 * k - 1) * (2 * k - 1);
}
int fibre_nodes_per_cell(int degree, Element element) {
  const int k = degree * element_order(element);
  return (2 * k + 1) * (2 * k + 1);
}

namespace {

// The fine grid that holds every node of a cell: k = degree·order levels from the rim to the
// cell's square, n = 4k intervals per cell edge, o grid steps per element edge; a the cell
// size, r the fibre radius.
struct FineGrid {
  int k, n, o;
  double a, r;
};

// The physical points of the block's matrix, by their fine grid index over the whole block
// (ex·n + 1) × (ey·n + 1): the copies a shared cell edge gives one place are one point.
struct BlockPoints {
  int columns = 0, rows = 0;  // ex·n + 1, ey·n + 1
  std::vector<int> point;     // block grid index -> point, −1 before its first node
  int& at(int gx, int gy) { return point[gx + columns * gy]; }
};

// A new point for node v with the sides it lies on.
int new_point(Mesh& mesh, std::uint8_t sides) {
  mesh.point_sides.push_back(sides);
  return mesh.n_points() - 1;
}

// Cell (cx, cy)'s matrix subdomain, its hole's rim on the circle about c: nodes (the outer
// square from integer grid coordinates of the whole block, so that neighbouring cells produce
// bitwise identical shared nodes; their points by that block grid index), then triangles.
// Returns grid index -> node.
std::vector<int> add_matrix(Mesh& mesh, std::vector<char>& keep, BlockPoints& points, const FineGrid& g, int cx, int cy,
                            int cell, const Eigen::Vector2d& cell_centre, const Eigen::Vector2d& c) {
  const int k = g.k, n = g.n, o = g.o;
  const double a = g.a, r = g.r;
  Subdomain matrix{false, -1, cell, mesh.n_nodes(), 0, static_cast<int>(mesh.triangles.size()), 0};
  std::vector<int> grid((n + 1) * (n + 1), -1);
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      const int di = i - 2 * k, dj = j - 2 * k;
      const int l = std::max(std::abs(di), std::abs(dj));
      if (l < k) continue;  // inside the hole
      Eigen::Vector2d p;
      const Eigen::Vector2d square(a * static_cast<double>(cx * n + i) / n, a * static_cast<double>(cy * n + j) / n);
      if (l == 2 * k) {
        p = square;
      } else {
        const double theta = ring_angle(di, dj, l);
        const Eigen::Vector2d circle = c + r * Eigen::Vector2d(std::cos(theta), std::sin(theta));
        const Eigen::Vector2d s = cell_centre + (a / 2) * Eigen::Vector2d(double(di) / l, double(dj) / l);
        p = l == k ? circle : Eigen::Vector2d(circle + (double(l - k) / k) * (s - circle));
      }
      grid[i + (n + 1) * j] = mesh.n_nodes();
      mesh.nodes.push_back(p);
      keep.push_back(l == k || l == 2 * k);
      const int gx = cx * n + i, gy = cy * n + j;
      int& point = points.at(gx, gy);
      if (point < 0)
        point = new_point(mesh, (gx == 0 ? side_bit(left) : 0) | (gx == points.columns - 1 ? side_bit(right) : 0) |
                                    (gy == 0 ? side_bit(bottom) : 0) | (gy == points.rows - 1 ? side_bit(top) : 0));
      mesh.point_of.push_back(point);
    }
  }
  for (int j = 0; j < n; j += o) {
    for (int i = 0; i < n; i += o) {
      // A quad belongs to the matrix unless it lies inside the middle block.
      const bool in_hole = i >= k && i < 3 * k && j >= k && j < 3 * k;
      if (!in_hole) add_quad(mesh.nodes, keep, grid, n + 1, o, i, j, mesh.triangles);
    }
  }
  matrix.node_end = mesh.n_nodes();
  matrix.triangle_end = static_cast<int>(mesh.triangles.size());
  mesh.subdomains.push_back(matrix);
  return grid;
}

// Cell `cell`'s fibre subdomain about c: rings of its own grid, the outermost on the circle;
// every node its own point, inside the cell. Returns grid index -> node.
std::vector<int> add_fibre(Mesh& mesh, std::vector<char>& keep, const FineGrid& g, int cell, const Eigen::Vector2d& c) {
  const int k = g.k, o = g.o, m = 2 * k;
  const double r = g.r;
  // One fibre per cell, in cell order: the fibre's row of fibre_centres is its cell.
  Subdomain fibre{true, cell, cell, mesh.n_nodes(), 0, static_cast<int>(mesh.triangles.size()), 0};
  std::vector<int> fgrid((m + 1) * (m + 1));
  for (int j = 0; j <= m; ++j) {
    for (int i = 0; i <= m; ++i) {
      const int di = i - k, dj = j - k;
      const int l = std::max(std::abs(di), std::abs(dj));
      Eigen::Vector2d p = c;
      if (l == k) {
        const double theta = ring_angle(di, dj, l);
        p = c + r * Eigen::Vector2d(std::cos(theta), std::sin(theta));
      } else if (l > 0) {
        const double theta = ring_angle(di, dj, l);
        p = c + r * fibre_ring_radius(double(l) / k) * Eigen::Vector2d(std::cos(theta), std::sin(theta));
      }
      fgrid[i + (m + 1) * j] = mesh.n_nodes();
      mesh.nodes.push_back(p);
      keep.push_back(l == k);
      mesh.point_of.push_back(new_point(mesh, 0));
    }
  }
  for (int j = 0; j < m; j += o)
    for (int i = 0; i < m; i += o) add_quad(mesh.nodes, keep, fgrid, m + 1, o, i, j, mesh.triangles);
  fibre.node_end = mesh.n_nodes();
  fibre.triangle_end = static_cast<int>(mesh.triangles.size());
  mesh.subdomains.push_back(fibre);
  return fgrid;
}

// Interface pairs: the fibre rim (fibre grid level k) against the hole ring (matrix grid
// level k), walked counter-clockwise from angle 0.
void add_interface_pairs(Mesh& mesh, const FineGrid& g, int cell, const std::vector<int>& fgrid,
                         const std::vector<int>& grid) {
  const int k = g.k, n = g.n, m = 2 * k;
  std::vector<std::pair<int, std::array<int, 2>>> ring;
  for (int j = 0; j <= m; ++j) {
    for (int i = 0; i <= m; ++i) {
      const int di = i - k, dj = j - k;
      if (std::max(std::abs(di), std::abs(dj)) != k) continue;
      ring.push_back({perimeter_position(di, dj, k), {fgrid[i + (m + 1) * j], grid[(i + k) + (n + 1) * (j + k)]}});
    }
  }
  std::sort(ring.begin(), ring.end());
  for (const auto& [pos, pair] : ring) {
    mesh.interface_pairs.push_back(pair);
    mesh.interface_fibre.push_back(cell);
  }
}

// Glue pairs along shared cell edges (vertical edges: every node; horizontal edges: the left
// end node skipped where a vertical edge already ties it, keeping the rows independent), and
// the outer boundary counter-clockwise, a p2 edge's mid-side node the fine grid node half-way.
void add_glue_and_boundary(Mesh& mesh, const FineGrid& g, int ex, int ey,
                           const std::vector<std::vector<int>>& matrix_grid) {
  const int n = g.n, o = g.o;
  auto at = [&](int cell, int i, int j) { return matrix_grid[cell][i + (n + 1) * j]; };
  for (int cy = 0; cy < ey; ++cy)
    for (int cx = 0; cx + 1 < ex; ++cx)
      for (int j = 0; j <= n; ++j) mesh.glue_pairs.push_back({at(cx + ex * cy, n, j), at(cx + 1 + ex * cy, 0, j)});
  for (int cy = 0; cy + 1 < ey; ++cy)
    for (int cx = 0; cx < ex; ++cx)
      for (int i = (cx > 0 ? 1 : 0); i <= n; ++i)
        mesh.glue_pairs.push_back({at(cx + ex * cy, i, n), at(cx + ex * (cy + 1), i, 0)});
  const auto mid = [&](int cell, int i, int j) { return o == 1 ? -1 : at(cell, i, j); };
  for (int cy = 0; cy < ey; ++cy)
    for (int j = 0; j < n; j += o) {
      const int r = ex - 1 + ex * cy, l = ex * cy;
      mesh.boundary_edges[right].push_back({at(r, n, j), at(r, n, j + o), mid(r, n, j + 1)});
      mesh.boundary_edges[left].push_back({at(l, 0, j + o), at(l, 0, j), mid(l, 0, j + 1)});
    }
  for (int cx = 0; cx < ex; ++cx)
    for (int i = 0; i < n; i += o) {
      const int b = cx, t = cx + ex * (ey - 1);
      mesh.boundary_edges[bottom].push_back({at(b, i, 0), at(b, i + o, 0), mid(b, i + 1, 0)});
      mesh.boundary_edges[top].push_back({at(t, i + o, n), at(t, i, n), mid(t, i + 1, n)});
    }
}

// The periodic pairs of the block's grid: right column to left column upwards, then top row to
// bottom row rightwards.
void add_periodic_pairs(Mesh& mesh, BlockPoints& points) {
  const int X = points.columns - 1, Y = points.rows - 1;
  for (int gy = 0; gy <= Y; ++gy) mesh.periodic_pairs.push_back({points.at(X, gy), points.at(0, gy), right});
  for (int gx = 0; gx <= X; ++gx) mesh.periodic_pairs.push_back({points.at(gx, Y), points.at(gx, 0), top});
}

}  // namespace

Mesh build_mesh(const Geometry& geometry) {
  Mesh mesh;
  mesh.geometry = geometry;
  const int o = element_order(geometry.element);  // fine grid steps per element edge
  mesh.triangles = Triangles(o == 1 ? 3 : 6);
  const int k = geometry.degree * o;  // degree of the fine grid that holds every node
  const FineGrid g{k, 4 * k, o, geometry.cell_size, geometry.fibre_radius};
  const int ex = geometry.cells[0], ey = geometry.cells[1];
  const int n_cells = ex * ey;
  mesh.nodes.reserve(static_cast<std::size_t>(n_cells) * (matrix_nodes_per_cell(k) + fibre_nodes_per_cell(k)));
  std::vector<char> keep;  // per node: its mapped position lies on the circle or a cell edge
  std::vector<std::vector<int>> matrix_grid(n_cells);  // grid index -> global node of each cell's matrix
  BlockPoints points{ex * g.n + 1, ey * g.n + 1, {}};
  points.point.assign(static_cast<std::size_t>(points.columns) * points.rows, -1);
  for (int cy = 0; cy < ey; ++cy) {
    for (int cx = 0; cx < ex; ++cx) {
      const int cell = cx + ex * cy;
      const Eigen::Vector2d cell_centre((cx + 0.5) * g.a, (cy + 0.5) * g.a);
      const Eigen::Vector2d c = cell_centre + Eigen::Vector2d(geometry.fibre_offset[0], geometry.fibre_offset[1]);
      mesh.fibre_centres.push_back(c);
      mesh.fibre_radii.push_back(geometry.fibre_radius);
      const int matrix_index = static_cast<int>(mesh.subdomains.size());
      matrix_grid[cell] = add_matrix(mesh, keep, points, g, cx, cy, cell, cell_centre, c);
      const int fibre_index = static_cast<int>(mesh.subdomains.size());
      const std::vector<int> fgrid = add_fibre(mesh, keep, g, cell, c);
      for (int index : {matrix_index, fibre_index})
        for (int t = mesh.subdomains[index].triangle_begin; t < mesh.subdomains[index].triangle_end; ++t)
          mesh.triangle_subdomain.push_back(index);
      add_interface_pairs(mesh, g, cell, fgrid, matrix_grid[cell]);
    }
  }
  add_glue_and_boundary(mesh, g, ex, ey, matrix_grid);
  add_periodic_pairs(mesh, points);
  return mesh;
}

double corner_area(const Mesh& mesh, int t) {
  const auto tri = mesh.triangles[t];
  const Eigen::Vector2d e1 = mesh.nodes[tri[1]] - mesh.nodes[tri[0]];
  const Eigen::Vector2d e2 = mesh.nodes[tri[2]] - mesh.nodes[tri[0]];
  return 0.5 * (e1.x() * e2.y() - e1.y() * e2.x());
}

std::vector<Eigen::Vector2d> triangle_points(const Mesh& mesh, int t) {
  std::vector<Eigen::Vector2d> x;
  for (int v : mesh.triangles[t]) x.push_back(mesh.nodes[v]);
  return x;
}

int side_of(const Mesh& mesh, const Eigen::Vector2d& a, const Eigen::Vector2d& b, double eps) {
  const double W = mesh.block_width(), H = mesh.block_height();
  if (std::abs(a.x()) < eps && std::abs(b.x()) < eps) return left;
  if (std::abs(a.x() - W) < eps && std::abs(b.x() - W) < eps) return right;
  if (std::abs(a.y()) < eps && std::abs(b.y()) < eps) return bottom;
  if (std::abs(a.y() - H) < eps && std::abs(b.y() - H) < eps) return top;
  return -1;
}

double side_tolerance(const Mesh& mesh) { return node_reach(std::max(mesh.block_width(), mesh.block_height())); }

std::vector<int> point_nodes(const Mesh& mesh) {
  std::vector<int> node(mesh.n_points(), -1);
  for (int v = 0; v < mesh.n_nodes(); ++v) node[mesh.point_of[v]] = v;
  return node;
}

std::vector<char> fibre_nodes(const Mesh& mesh) {
  std::vector<char> on_fibre(mesh.n_nodes(), 0);
  for (const Subdomain& sub : mesh.subdomains)
    if (sub.is_fibre) std::fill(on_fibre.begin() + sub.node_begin, on_fibre.begin() + sub.node_end, 1);
  return on_fibre;
}

std::vector<int> side_points(const Mesh& mesh, int side) {
  const std::vector<char> on_fibre = fibre_nodes(mesh);
  const int axis = (side == left || side == right) ? 1 : 0;
  std::vector<char> seen(mesh.n_points(), 0);
  std::vector<std::tuple<double, char, int>> along;  // (coordinate along the side, fibre, point)
  for (int v = 0; v < mesh.n_nodes(); ++v) {
    const int p = mesh.point_of[v];
    if (!(mesh.point_sides[p] & side_bit(side)) || seen[p]) continue;
    seen[p] = 1;
    along.emplace_back(mesh.nodes[v][axis], on_fibre[v], p);
  }
  std::sort(along.begin(), along.end());
  std::vector<int> points;
  for (const auto& [x, fibre, p] : along) points.push_back(p);
  return points;
}

std::uint8_t sides_at(const Mesh& mesh, const Eigen::Vector2d& x, double tol) {
  const double W = mesh.block_width(), H = mesh.block_height();
  return (std::abs(x.x()) <= tol ? side_bit(left) : 0) | (std::abs(x.x() - W) <= tol ? side_bit(right) : 0) |
         (std::abs(x.y()) <= tol ? side_bit(bottom) : 0) | (std::abs(x.y() - H) <= tol ? side_bit(top) : 0);
}

namespace {

// point_problem's part for periodic_pairs, given every point's first node.
std::string periodic_problem(const Mesh& mesh, const std::vector<int>& first, const std::vector<char>& on_fibre) {
  const int P = mesh.n_points();
  const double tol = side_tolerance(mesh);
  // Per point how often it is the point (the partner) of a right pair [0] and of a top pair [1].
  std::vector<std::array<int, 2>> as_point(P, {0, 0}), as_partner(P, {0, 0});
  for (const auto& [side, opposite] : {std::pair{right, left}, std::pair{top, bottom}}) {
    int n = 0, m = 0;
    for (int p = 0; p < P; ++p) {
      n += (mesh.point_sides[p] & side_bit(side)) != 0;
      m += (mesh.point_sides[p] & side_bit(opposite)) != 0;
    }
    if (n != m)
      return std::string("point_sides: the ") + side_names[side] + " side has " + std::to_string(n) + " points, the " +
             side_names[opposite] + " side " + std::to_string(m);
  }
  for (std::size_t i = 0; i < mesh.periodic_pairs.size(); ++i) {
    const auto [p, q, side] = mesh.periodic_pairs[i];
    const std::string pair = "periodic_pairs: pair " + std::to_string(i);
    if (p < 0 || p >= P || q < 0 || q >= P || (side != right && side != top))
      return pair + ": a point or its side out of range";
    const int opposite = side == right ? left : bottom;
    const Eigen::Vector2d shift =
        side == right ? Eigen::Vector2d(mesh.block_width(), 0) : Eigen::Vector2d(0, mesh.block_height());
    if (!(mesh.point_sides[p] & side_bit(side)) || !(mesh.point_sides[q] & side_bit(opposite)) ||
        on_fibre[first[p]] != on_fibre[first[q]] || (mesh.nodes[first[p]] - shift - mesh.nodes[first[q]]).norm() > tol)
      return pair + ": the partner of a point on the " + side_names[side] + " side is not its copy on the " +
             side_names[opposite] + " side";
    ++as_point[p][side == top];
    ++as_partner[q][side == top];
  }
  for (const auto& [side, opposite] : {std::pair{right, left}, std::pair{top, bottom}}) {
    for (int p = 0; p < P; ++p)
      if (((mesh.point_sides[p] & side_bit(side)) && as_point[p][side == top] != 1) ||
          ((mesh.point_sides[p] & side_bit(opposite)) && as_partner[p][side == top] != 1))
        return "periodic_pairs: point " + std::to_string(p) + " on the " +
               side_names[(mesh.point_sides[p] & side_bit(side)) ? side : opposite] +
               " side is not in exactly one pair";
  }
  return "";
}

}  // namespace

std::string point_problem(const Mesh& mesh) {
  const int N = mesh.n_nodes(), P = mesh.n_points();
  if (static_cast<int>(mesh.point_of.size()) != N) return "point_of: not one point per node";
  const double tol = side_tolerance(mesh);
  const std::vector<char> on_fibre = fibre_nodes(mesh);
  std::vector<int> first(P, -1);
  for (int v = 0; v < N; ++v) {
    const int p = mesh.point_of[v];
    if (p < 0 || p >= P) return "point_of: node " + std::to_string(v) + " has a point out of range";
    if (first[p] < 0) first[p] = v;
    // Copies of one place in the matrix, or a fibre node alone.
    const int u = first[p];
    if (u != v && (on_fibre[u] || on_fibre[v] || (mesh.nodes[u] - mesh.nodes[v]).norm() > tol))
      return "point_of: nodes " + std::to_string(u) + " and " + std::to_string(v) +
             " share a point but are not copies of one place in the matrix";
    if (sides_at(mesh, mesh.nodes[v], tol) != mesh.point_sides[p])
      return "point_sides: point " + std::to_string(p) + " of node " + std::to_string(v) +
             " is not marked with the sides the node lies on";
  }
  for (int p = 0; p < P; ++p)
    if (first[p] < 0) return "point_sides: point " + std::to_string(p) + " has no node";
  for (std::size_t q = 0; q < mesh.glue_pairs.size(); ++q)
    if (mesh.point_of[mesh.glue_pairs[q][0]] != mesh.point_of[mesh.glue_pairs[q][1]])
      return "glue_pairs: pair " + std::to_string(q) + " joins two points (point_of)";
  for (std::size_t q = 0; q < mesh.interface_pairs.size(); ++q)
    if (mesh.point_of[mesh.interface_pairs[q][0]] == mesh.point_of[mesh.interface_pairs[q][1]])
      return "interface_pairs: pair " + std::to_string(q) + " joins the nodes of one point (point_of)";
  return periodic_problem(mesh, first, on_fibre);
}

namespace {

// An RVE's rim edges, from its fibre triangles: the edges of a fibre piece used by one of its
// triangles only (its outline) whose end nodes are both on the rim, except those along the
// rectangle's sides (a piece's straight cut). A rim point on the right or top side takes the pair
// of its periodic partner on the left or bottom side (a corner's through both).
std::vector<RimEdge> rve_interface_edges(const Mesh& mesh) {
  std::vector<int> pair_of(mesh.n_points(), -1), partner(mesh.n_points(), -1);
  for (int p = 0; p < static_cast<int>(mesh.interface_pairs.size()); ++p)
    pair_of[mesh.point_of[mesh.interface_pairs[p][0]]] = p;
  // Right pairs first: a top-right corner goes left, then down.
  for (const PeriodicPair& pp : mesh.periodic_pairs)
    if (partner[pp.point] < 0) partner[pp.point] = pp.partner;
  const auto rim_pair = [&](int v) {
    int p = mesh.point_of[v];
    while (pair_of[p] < 0 && partner[p] >= 0) p = partner[p];
    return pair_of[p];
  };
  std::map<std::pair<int, int>, std::pair<int, Edge>> uses;  // sorted corner pair -> (count, edge)
  const int width = mesh.triangles.width();
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (!mesh.subdomains[mesh.triangle_subdomain[t]].is_fibre) continue;
    const auto tri = mesh.triangles[t];
    for (int c = 0; c < 3; ++c) {
      const int a = tri[c], b = tri[(c + 1) % 3];
      auto& [count, edge] = uses[std::minmax(a, b)];
      ++count;
      edge = {a, b, width == 6 ? tri[3 + c] : -1};
    }
  }
  std::vector<RimEdge> edges;
  for (const auto& [corners, use] : uses) {
    const auto& [count, e] = use;
    if (count != 1 || (mesh.point_sides[mesh.point_of[e.a]] & mesh.point_sides[mesh.point_of[e.b]])) continue;
    const int pa = rim_pair(e.a), pb = rim_pair(e.b), pm = e.mid < 0 ? -1 : rim_pair(e.mid);
    if (pa < 0 || pb < 0 || (e.mid >= 0 && pm < 0)) continue;
    edges.push_back({{pa, pb, pm}, e});
  }
  return edges;
}

}  // namespace

std::vector<RimEdge> interface_edges(const Mesh& mesh) {
  if (mesh.geometry.rve()) return rve_interface_edges(mesh);
  const int n = static_cast<int>(mesh.interface_pairs.size());
  const int o = element_order(mesh.element());
  std::vector<RimEdge> edges;
  const auto node = [&](int p) { return p < 0 ? -1 : mesh.interface_pairs[p][0]; };
  // Pairs are stored cell by cell, counter-clockwise from angle 0, every rim node of the cell
  // once: an edge starts at every o-th pair of its cell and ends o pairs further, cyclically.
  int begin = 0;
  while (begin < n) {
    int end = begin;
    while (end < n && mesh.interface_fibre[end] == mesh.interface_fibre[begin]) ++end;
    const int m = end - begin;
    for (int i = 0; i + o <= m; i += o) {
      const Edge pairs{begin + i, begin + (i + o) % m, o == 1 ? -1 : begin + i + 1};
      edges.push_back({pairs, {node(pairs.a), node(pairs.b), node(pairs.mid)}});
    }
    begin = end;
  }
  return edges;
}

double minimum_angle_deg(const Mesh& mesh) {
  double smallest = 180;
  for (const auto tri : mesh.triangles) {
    for (int v = 0; v < 3; ++v) {
      const Eigen::Vector2d p = mesh.nodes[tri[v]];
      const Eigen::Vector2d e1 = mesh.nodes[tri[(v + 1) % 3]] - p;
      const Eigen::Vector2d e2 = mesh.nodes[tri[(v + 2) % 3]] - p;
      const double angle = std::atan2(std::abs(e1.x() * e2.y() - e1.y() * e2.x()), e1.dot(e2));
      smallest = std::min(smallest, angle * 180 / std::numbers::pi);
    }
  }
  return smallest;
}

}  // namespace dualcell::mesh
