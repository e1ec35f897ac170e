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
#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "core/scene.hpp"

namespace dualcell::mesh {

struct Subdomain {
  bool is_fibre = false;
  // The mapped block: the cell cx + ex*cy. An RVE: a fibre piece's index into
  // Mesh::fibre_centres; −1 for the matrix's subdomains.
  int cell = 0;
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
  std::vector<int> interface_cell;                  // fibre (index into fibre_centres) of each interface pair
  std::vector<std::array<int, 2>> glue_pairs;       // (matrix node, matrix node of a neighbour)
  // Outer boundary edges per Side, oriented counter-clockwise around the block, so the
  // outward normal of edge (a, b) is (b - a) rotated by -90°.
  std::array<std::vector<Edge>, 4> boundary_edges;

  Element element() const { return geometry.element; }
  int n_nodes() const { return static_cast<int>(nodes.size()); }
  int dim_u() const { return 2 * n_nodes(); }
  int n_cells() const { return geometry.cells[0] * geometry.cells[1]; }
  int n_fibres() const { return static_cast<int>(fibre_centres.size()); }
  double block_width() const { return geometry.width(); }
  double block_height() const { return geometry.height(); }
};

// Builds the mesh of a validated geometry.
Mesh build_mesh(const Geometry& geometry);

// The side of the block (Side) on which both points a and b lie, within eps; −1 for none.
int side_of(const Mesh& mesh, const Eigen::Vector2d& a, const Eigen::Vector2d& b, double eps);

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
