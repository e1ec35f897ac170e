#pragma once
// The mapped mesh of a block of ex × ey fibre cells (docs/method.md §2).
//
// Each cell gives two subdomains, each with its own nodes (interface nodes duplicated):
//   * the matrix: the (4k+1)² square grid of the cell minus the interior of its middle
//     (2k+1)² block; the middle block's boundary ring goes to equal angles on the circle,
//     and every node in between lies on the straight segment from its circle point to its
//     square point, at the fraction given by its ring level (segments split evenly);
//   * the fibre: the (2k+1)² grid whose concentric square rings go to concentric circles,
//     radii pushed slightly towards the rim.
// Quads are split along the shorter diagonal into triangles, counter-clockwise.
//
// Quadratic (p2) meshes of degree k are built on the grid of degree 2k: every quad of the
// degree-k grid is a 2×2 block of the fine grid, whose corner nodes are the triangle corners
// (the same points as the p1 mesh of degree k) and whose edge midpoints and centre are the
// mid-side nodes. Those on the fibre rim and on the hole come from the map, so they lie on the
// exact circle (isoparametric: curved interface edges); every other mid-side node sits at the
// midpoint of its edge (straight edges; the cell edges are straight anyway).
//
// Interface pairs (fibre node, matrix node) coincide exactly, and so do glue pairs
// (matrix nodes of neighbouring cells on a shared edge; at a cross point of four cells only
// three pairs, so that the gluing rows are linearly independent).
//
// Point identity (Mesh::point_of, point_sides, periodic_pairs) is recorded by the mesher, which
// knows it exactly (grid indices; gmsh's node tags and periodic copies), so that no consumer
// compares coordinates to find a copy, a side or a periodic partner.
#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/scene.hpp"

namespace dualcell::mesh {

struct Subdomain {
  bool is_fibre = false;
  // A fibre subdomain's circle: its row of Mesh::fibre_centres (an RVE's fibre cut by the edges
  // is one piece per side, each a fibre of its own); −1 for the matrix.
  int fibre = -1;
  // The mapped block's cell cx + ex·cy that the subdomain fills (its fibre or its matrix); −1 in
  // an RVE.
  int cell = -1;
  int node_begin = 0;  // rows [node_begin, node_end) of Mesh::nodes
  int node_end = 0;
  int triangle_begin = 0;  // rows [triangle_begin, triangle_end) of Mesh::triangles
  int triangle_end = 0;
  int n_nodes() const { return node_end - node_begin; }
  int n_triangles() const { return triangle_end - triangle_begin; }
};

// Triangles as rows of one width: 3 nodes (p1) or 6 (p2). Node order of a row: the three
// corners counter-clockwise, then (p2) the mid-side nodes of the edges (0,1), (1,2), (2,0) — the
// order of VTK/XDMF `Triangle_6` and CalculiX CPE6.
class Triangles {
 public:
  explicit Triangles(int width = 3) : width_(width) {}
  int width() const { return width_; }
  std::size_t size() const { return nodes_.size() / width_; }
  std::span<const int> operator[](std::size_t t) const { return {nodes_.data() + t * width_, std::size_t(width_)}; }
  void push_back(std::span<const int> row) { nodes_.insert(nodes_.end(), row.begin(), row.end()); }
  void push_back(std::initializer_list<int> row) { nodes_.insert(nodes_.end(), row.begin(), row.end()); }
  const std::vector<int>& flat() const { return nodes_; }
  bool operator==(const Triangles&) const = default;

  class iterator {
   public:
    iterator(const Triangles* t, std::size_t i) : t_(t), i_(i) {}
    std::span<const int> operator*() const { return (*t_)[i_]; }
    iterator& operator++() {
      ++i_;
      return *this;
    }
    bool operator!=(const iterator& o) const { return i_ != o.i_; }

   private:
    const Triangles* t_;
    std::size_t i_;
  };
  iterator begin() const { return {this, 0}; }
  iterator end() const { return {this, size()}; }

 private:
  int width_;
  std::vector<int> nodes_;
};

// An edge of the outer boundary: end nodes a, b and, for p2, the mid-side node (else −1).
struct Edge {
  int a = -1, b = -1, mid = -1;
  bool operator==(const Edge&) const = default;
};

// Sides of the block's outer boundary, in the order used everywhere (files, loads).
enum Side { left = 0, right = 1, bottom = 2, top = 3 };
inline constexpr std::array<const char*, 4> side_names{"left", "right", "bottom", "top"};
// The bit of a side in Mesh::point_sides.
inline constexpr std::uint8_t side_bit(int side) { return std::uint8_t(1u << side); }

// A point on the right (top) side and its periodic partner on the left (bottom) side: the same
// place one period Lx (Ly) back, of the same material (a fibre's point pairs with a fibre's).
struct PeriodicPair {
  int point = -1, partner = -1;
  Side side = right;  // of `point`: right or top
  bool operator==(const PeriodicPair&) const = default;
};

struct Mesh {
  Geometry geometry;
  std::vector<Eigen::Vector2d> nodes;  // all subdomains' nodes stacked
  Triangles triangles;                 // global node indices, counter-clockwise
  std::vector<int> triangle_subdomain;
  std::vector<Subdomain> subdomains;
  // Per fibre subdomain (a cell's fibre, or a piece of an RVE's fibre: a fibre crossing an edge
  // is one piece per side, each with the centre of its own periodic image): the exact circle.
  std::vector<Eigen::Vector2d> fibre_centres;
  std::vector<double> fibre_radii;
  std::vector<std::array<int, 2>> interface_pairs;  // (fibre node, matrix node)
  std::vector<int> interface_fibre;                 // fibre (index into fibre_centres) of each interface pair
  std::vector<std::array<int, 2>> glue_pairs;       // (matrix node, matrix node of a neighbour)
  // Outer boundary edges per Side, oriented counter-clockwise around the block, so the
  // outward normal of edge (a, b) is (b - a) rotated by -90°.
  std::array<std::vector<Edge>, 4> boundary_edges;
  // Physical points. point_of[v]: the point of node v; the copies of one place in the matrix's
  // subdomains (glued) share one point, while a fibre node and its matrix interface partner are
  // two points (joined by interface rows, which may open). Points are numbered in the order of
  // their first node; a point's rows act on its last node (point_nodes).
  std::vector<int> point_of;
  // Per point: the sides of the block it lies on (side_bit; a corner has two).
  std::vector<std::uint8_t> point_sides;
  // Every point on the right side with its partner on the left, ordered upwards, then every
  // point on the top with its partner on the bottom, ordered rightwards; at one place the
  // matrix's point before the fibre's. A corner point has a pair on each of its sides.
  std::vector<PeriodicPair> periodic_pairs;

  Element element() const { return geometry.element; }
  int n_nodes() const { return static_cast<int>(nodes.size()); }
  int dim_u() const { return 2 * n_nodes(); }
  int n_cells() const { return geometry.cells[0] * geometry.cells[1]; }
  int n_fibres() const { return static_cast<int>(fibre_centres.size()); }
  double block_width() const { return geometry.width(); }
  double block_height() const { return geometry.height(); }
  int n_points() const { return static_cast<int>(point_sides.size()); }
};

// Builds the mesh of a validated geometry.
Mesh build_mesh(const Geometry& geometry);

// The side of the block (Side) on which both points a and b lie, within eps; −1 for none. For
// the meshers and the reader's check; everything else reads Mesh::point_sides.
int side_of(const Mesh& mesh, const Eigen::Vector2d& a, const Eigen::Vector2d& b, double eps);
// The tolerance of the meshers and of the reader's check for "on a side" and "at the same place
// on the opposite side": node_reach (core/edge_loads.hpp) of the block's larger side.
double side_tolerance(const Mesh& mesh);
// The sides of the block position x lies on, within tol, as side bits (a corner: two).
std::uint8_t sides_at(const Mesh& mesh, const Eigen::Vector2d& x, double tol);

// 1 for the nodes of fibre subdomains.
std::vector<char> fibre_nodes(const Mesh& mesh);
// Per point its last node: the node the point's constraint rows act on.
std::vector<int> point_nodes(const Mesh& mesh);
// The points on `side` (from point_sides) in order along it, left to right or bottom to top; at
// one place the matrix's point before the fibre's. Ordered by the coordinate along the side
// (only the order, never which points are on it).
std::vector<int> side_points(const Mesh& mesh, int side);
// What is wrong with point_of, point_sides and periodic_pairs, or "" when nothing is: sizes and
// ranges; glued copies of one point, interface pairs of two; every point's sides those its nodes
// lie on; every point of the right (top) side in exactly one pair, with a partner of the same
// material on the left (bottom) side at the same place one period back, and every point of the
// left (bottom) side the partner of exactly one — so opposite sides have equally many points.
// Within side_tolerance. The meshers' own check and the reader's.
std::string point_problem(const Mesh& mesh);

// Smallest interior angle over all triangles (of their corners), in degrees.
double minimum_angle_deg(const Mesh& mesh);
// Signed area of the straight triangle through the corners of triangle t (positive when
// counter-clockwise); the area of a curved p2 element is fem::element_area.
double corner_area(const Mesh& mesh, int t);
// Coordinates of the nodes of triangle t, in the row's order.
std::vector<Eigen::Vector2d> triangle_points(const Mesh& mesh, int t);
// Interface edges of the rim: per edge the interface pairs (indices into interface_pairs) of its
// end nodes and, for p2, its mid-side node (else −1), counter-clockwise cell by cell; and the
// fibre nodes they run through. An RVE's rim point on its right or top side has no pair of its
// own (it is the periodic copy of the point on the left or bottom, whose pair it shares: one
// physical point, one pair), so there an edge's pair is the copy's and its node its own.
struct RimEdge {
  Edge pairs, nodes;
};
std::vector<RimEdge> interface_edges(const Mesh& mesh);
// Number of nodes of one cell's matrix and fibre subdomains for degree k and element e.
int matrix_nodes_per_cell(int degree, Element element = Element::p1);
int fibre_nodes_per_cell(int degree, Element element = Element::p1);

}  // namespace dualcell::mesh
