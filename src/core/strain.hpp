#pragma once
// A plane macro strain in its two conventions, named so that a factor 2 on the shear cannot be
// lost between them:
//   tensor shear       (εxx, εyy, εxy): the symmetric gradient's components, what the solver
//                      and the sweep compute (feti::Solution::strain, sweep::Step::strain, the
//                      fuse's strains);
//   engineering shear  (εxx, εyy, γxy = 2εxy): what the laws use (law::CellResponse, the fitted
//                      compliances S, the cone-wise law, the CSV and umat interfaces), with which
//                      σ̄·ε̄ is the work per unit volume.
// Stresses have one convention, (σxx, σyy, σxy).
#include <Eigen/Core>

namespace dualcell {

inline Eigen::Vector3d engineering_from_tensor(const Eigen::Vector3d& tensor) {
  return {tensor(0), tensor(1), 2 * tensor(2)};
}

// σ:ε for a tensor-shear strain, σxx εxx + σyy εyy + 2 σxy εxy: the work per unit volume, or
// with a unit stress N the strain along the load.
inline double work_with_tensor_strain(const Eigen::Vector3d& sigma, const Eigen::Vector3d& tensor) {
  return sigma(0) * tensor(0) + sigma(1) * tensor(1) + 2 * sigma(2) * tensor(2);
}

}  // namespace dualcell
