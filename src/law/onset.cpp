#include "law/onset.hpp"

#include <algorithm>
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

OnsetCheck check_against_sweep(const OnsetSurface& surface) {
  OnsetCheck check;
  for (std::size_t k = 0; k < surface.path_onset.size() && k < surface.path_sweep_onset.size(); ++k) {
    if (std::isnan(surface.path_sweep_onset[k])) continue;
    check.worst_relative =
        std::max(check.worst_relative, std::abs(surface.path_onset[k] / surface.path_sweep_onset[k] - 1));
    ++check.paths;
  }
  return check;
}

}  // namespace dualcell::law
