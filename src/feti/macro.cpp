#include "feti/macro.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "fem/assembly.hpp"
#include "feti/constraints.hpp"

namespace dualcell::feti {

Eigen::Vector3d boundary_strain(const mesh::Mesh& mesh, const Eigen::VectorXd& u) {
  Eigen::Matrix2d H = Eigen::Matrix2d::Zero();  // ∮ u ⊗ n ds
  for (const auto& side : mesh.boundary_edges)
    for (const mesh::Edge& edge : side) H += fem::edge_moment(mesh, edge, u);
  H /= mesh.block_width() * mesh.block_height();
  return {H(0, 0), H(1, 1), 0.5 * (H(0, 1) + H(1, 0))};
}

Eigen::MatrixXd boundary_strain_matrix(const mesh::Mesh& mesh, int n_dofs) {
  // boundary_strain is linear in u and reads the nodes of the outer edges only: its columns
  // are its values at the unit vectors of those nodes' DOFs.
  Eigen::MatrixXd W = Eigen::MatrixXd::Zero(3, n_dofs);
  std::vector<int> nodes;
  for (const auto& side : mesh.boundary_edges)
    for (const mesh::Edge& edge : side)
      for (int v : {edge.a, edge.b, edge.mid})
        if (v >= 0) nodes.push_back(v);
  std::sort(nodes.begin(), nodes.end());
  nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  Eigen::VectorXd unit = Eigen::VectorXd::Zero(n_dofs);
  for (int v : nodes)
    for (int c = 0; c < 2; ++c) {
      unit(2 * v + c) = 1;
      W.col(2 * v + c) = boundary_strain(mesh, unit);
      unit(2 * v + c) = 0;
    }
  return W;
}

Eigen::Vector3d average_stress(const mesh::Mesh& mesh, const Material& fibre, const Material& matrix,
                               const Eigen::VectorXd& u, const fem::Uniform& z, double* zz) {
  const fem::ElementStresses stress = fem::element_stresses(mesh, fibre, matrix, u, z);
  const double volume = mesh.block_width() * mesh.block_height();
  if (zz) *zz = stress.zz_average.dot(stress.area) / volume;
  const Eigen::Vector3d sum = stress.average.transpose() * stress.area;  // Σ_t ∫_t σ dA
  return sum / volume;
}

SolutionFields solution_fields(const mesh::Mesh& mesh, const Scene& scene, const Eigen::VectorXd& u,
                               const fem::Uniform& z) {
  SolutionFields out;
  out.stress = fem::element_stresses(mesh, scene.fibre, scene.matrix, u, z);
  out.opening.reserve(mesh.interface_pairs.size());
  for (std::size_t p = 0; p < mesh.interface_pairs.size(); ++p) {
    const auto [fn, mn] = mesh.interface_pairs[p];
    const Eigen::Vector2d n = interface_normal(mesh, static_cast<int>(p));
    out.opening.push_back(n.dot(u.segment<2>(2 * mn) - u.segment<2>(2 * fn)));
  }
  return out;
}

}  // namespace dualcell::feti
