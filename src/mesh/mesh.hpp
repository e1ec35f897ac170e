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
// Quads are split along the shorter diagonal into linear triangles, counter-clockwise.
// Interface pairs (fibre node, matrix node) coincide exactly, and so do glue pairs
// (matrix nodes of neighbouring cells on a shared edge; at a cross point of four cells only
// three pairs, so that the gluing rows are linearly independent).
#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "core/scene.hpp"

namespace dualcell::mesh {

struct Subdomain {
  bool is_fibre = false;
  int cell = 0;        // cx + ex*cy
  int node_begin = 0;  // rows [node_begin, node_end) of Mesh::nodes
  int node_end = 0;
  int triangle_begin = 0;  // rows [triangle_begin, triangle_end) of Mesh::triangles
  int triangle_end = 0;
  int n_nodes() const { return node_end - node_begin; }
  int n_triangles() const { return triangle_end - triangle_begin; }
};

// Sides of the block's outer boundary, in the order used everywhere (files, loads).
enum Side { left = 0, right = 1, bottom = 2, top = 3 };
inline constexpr std::array<const char*, 4> side_names{"left", "right", "bottom", "top"};

struct Mesh {
  Geometry geometry;
  std::vector<Eigen::Vector2d> nodes;         // all subdomains' nodes stacked
  std::vector<std::array<int, 3>> triangles;  // global node indices, counter-clockwise
  std::vector<int> triangle_subdomain;
  std::vector<Subdomain> subdomains;
  std::vector<Eigen::Vector2d> fibre_centres;       // one per cell, exact circle centre
  std::vector<std::array<int, 2>> interface_pairs;  // (fibre node, matrix node)
  std::vector<int> interface_cell;                  // cell of each interface pair
  std::vector<std::array<int, 2>> glue_pairs;       // (matrix node, matrix node of a neighbour)
  // Outer boundary edges per Side, oriented counter-clockwise around the block, so the
  // outward normal of edge (a, b) is (b - a) rotated by -90°.
  std::array<std::vector<std::array<int, 2>>, 4> boundary_edges;

  int n_nodes() const { return static_cast<int>(nodes.size()); }
  int dim_u() const { return 2 * n_nodes(); }
  int n_cells() const { return geometry.cells[0] * geometry.cells[1]; }
  double block_width() const { return geometry.cells[0] * geometry.cell_size; }
  double block_height() const { return geometry.cells[1] * geometry.cell_size; }
};

// Builds the mesh of a validated geometry.
Mesh build_mesh(const Geometry& geometry);

// Smallest interior angle over all triangles, in degrees.
double minimum_angle_deg(const Mesh& mesh);
// Signed area of triangle t (positive when counter-clockwise).
double triangle_area(const Mesh& mesh, int t);
// Number of nodes of one cell's matrix and fibre subdomains for degree k.
int matrix_nodes_per_cell(int degree);
int fibre_nodes_per_cell(int degree);

}  // namespace dualcell::mesh
