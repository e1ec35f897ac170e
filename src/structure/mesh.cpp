// The rectangle's mesh of a structure of homogeneous cells: m × m squares of two triangles per
// cell, p1 or p2.
#include <algorithm>
#include <cmath>

#include "fem/edge_conditions.hpp"
#include "structure/structure.hpp"

namespace dualcell::structure {

int StructureMesh::node_at(const Eigen::Vector2d& x) const {
  const double size = std::max((nodes.colwise().maxCoeff() - nodes.colwise().minCoeff()).maxCoeff(), 1e-300);
  return fem::node_near(
      static_cast<int>(nodes.rows()), [&](int i) { return Eigen::Vector2d(nodes.row(i).transpose()); }, x, size);
}

StructureMesh build_structure_mesh(const StructureScene& scene) {
  const int q = element_order(scene.element), m = scene.elements_per_cell;
  const int squares_x = scene.nx * m, squares_y = scene.ny * m;
  const int Nx = q * squares_x + 1, Ny = q * squares_y + 1;
  const double h = scene.cell_size / (m * q);
  StructureMesh mesh;
  mesh.nodes.resize(static_cast<Eigen::Index>(Nx) * Ny, 2);
  for (int j = 0; j < Ny; ++j)
    for (int i = 0; i < Nx; ++i) mesh.nodes.row(i + Nx * j) << i * h, j * h;
  const auto id = [&](int i, int j) { return i + Nx * j; };
  const int per = q == 1 ? 3 : 6;
  mesh.triangles.resize(2 * squares_x * squares_y, per);
  int t = 0;
  for (int sy = 0; sy < squares_y; ++sy)
    for (int sx = 0; sx < squares_x; ++sx) {
      const int i0 = q * sx, j0 = q * sy;
      // Two counter-clockwise triangles split by the diagonal (0,0)–(1,1), in grid steps of q.
      const std::array<std::array<int, 2>, 3> corners[2] = {{{{0, 0}, {1, 0}, {1, 1}}}, {{{0, 0}, {1, 1}, {0, 1}}}};
      for (const auto& c : corners) {
        for (int k = 0; k < 3; ++k) mesh.triangles(t, k) = id(i0 + q * c[k][0], j0 + q * c[k][1]);
        if (q == 2)
          for (int k = 0; k < 3; ++k) {
            const auto& a = c[k];
            const auto& b = c[(k + 1) % 3];
            mesh.triangles(t, 3 + k) = id(i0 + a[0] + b[0], j0 + a[1] + b[1]);
          }
        mesh.cell.push_back(sx / m + scene.nx * (sy / m));
        ++t;
      }
    }
  for (int j = 0; j < Ny; ++j) mesh.edge_nodes[0].push_back(id(0, j)), mesh.edge_nodes[1].push_back(id(Nx - 1, j));
  for (int i = 0; i < Nx; ++i) mesh.edge_nodes[2].push_back(id(i, 0)), mesh.edge_nodes[3].push_back(id(i, Ny - 1));
  return mesh;
}

}  // namespace dualcell::structure
