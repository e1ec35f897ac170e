#include "law/onset.hpp"

#include <cmath>
#include <limits>

namespace dualcell::law {

double onset_measure(const OnsetSurface& surface, const Eigen::Vector3d& sigma) {
  if (!surface.linear) return std::numeric_limits<double>::quiet_NaN();
  if (surface.facets.rows() == 0) return -std::numeric_limits<double>::infinity();
  return (surface.facets * sigma).maxCoeff();
}

double onset_along(const OnsetSurface& surface, const Eigen::Vector3d& N) {
  const double phi = onset_measure(surface, N);
  if (std::isnan(phi)) return phi;
  return phi > 0 ? 1 / phi : std::numeric_limits<double>::infinity();
}

}  // namespace dualcell::law
