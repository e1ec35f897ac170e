#include "feti/macro.hpp"

#include <cmath>

#include "fem/assembly.hpp"

namespace dualcell::feti {

Eigen::Vector3d boundary_strain(const mesh::Mesh& mesh, const Eigen::VectorXd& u) {
  Eigen::Matrix2d H = Eigen::Matrix2d::Zero();  // ∮ u ⊗ n ds
  for (const auto& side : mesh.boundary_edges)
    for (const mesh::Edge& edge : side) H += fem::edge_moment(mesh, edge, u);
  H /= mesh.block_width() * mesh.block_height();
  return {H(0, 0), H(1, 1), 0.5 * (H(0, 1) + H(1, 0))};
}

Eigen::Vector3d average_stress(const mesh::Mesh& mesh, const Material& fibre, const Material& matrix,
                               const Eigen::VectorXd& u) {
  const fem::ElementStresses stress = fem::element_stresses(mesh, fibre, matrix, u);
  const Eigen::Vector3d sum = stress.average.transpose() * stress.area;  // Σ_t ∫_t σ dA
  return sum / (mesh.block_width() * mesh.block_height());
}

}  // namespace dualcell::feti
