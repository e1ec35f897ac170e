#include "feti/macro.hpp"

#include <cmath>

#include "fem/assembly.hpp"

namespace dualcell::feti {

Eigen::Vector3d boundary_strain(const mesh::Mesh& mesh, const Eigen::VectorXd& u) {
  Eigen::Matrix2d H = Eigen::Matrix2d::Zero();  // ∮ u ⊗ n ds
  for (const auto& side : mesh.boundary_edges)
    for (const auto& [a, b] : side) {
      const Eigen::Vector2d e = mesh.nodes[b] - mesh.nodes[a];
      const Eigen::Vector2d n_times_length(e.y(), -e.x());  // outward normal × edge length
      const Eigen::Vector2d u_mean = 0.5 * (u.segment<2>(2 * a) + u.segment<2>(2 * b));
      H += u_mean * n_times_length.transpose();
    }
  H /= mesh.block_width() * mesh.block_height();
  return {H(0, 0), H(1, 1), 0.5 * (H(0, 1) + H(1, 0))};
}

Eigen::Vector3d average_stress(const mesh::Mesh& mesh, const Material& fibre, const Material& matrix,
                               const Eigen::VectorXd& u) {
  const Eigen::MatrixXd stress = fem::element_stresses(mesh, fibre, matrix, u);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int t = 0; t < static_cast<int>(mesh.triangles.size()); ++t)
    sum += std::abs(mesh::triangle_area(mesh, t)) * stress.row(t).transpose();
  return sum / (mesh.block_width() * mesh.block_height());
}

}  // namespace dualcell::feti
