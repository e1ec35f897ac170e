#pragma once
// Unit directions of a load: the uniaxial stress along an angle, and points spread over the unit
// sphere.
#include <Eigen/Core>
#include <cmath>
#include <numbers>
#include <vector>

namespace dualcell {

// The uniaxial unit stress n⊗n along n = (cos θ, sin θ), θ in radians: (cos²θ, sin²θ, cos θ sin θ).
inline Eigen::Vector3d uniaxial_stress(double theta) {
  const double c = std::cos(theta), s = std::sin(theta);
  return {c * c, s * s, c * s};
}

// n points spread evenly over the unit sphere (a Fibonacci set: z = 1 − (2k + 1)/n, turning by the golden angle).
inline std::vector<Eigen::Vector3d> fibonacci_sphere(int n) {
  std::vector<Eigen::Vector3d> out;
  const double golden = std::numbers::pi * (3 - std::sqrt(5.0));  // the golden angle
  for (int k = 0; k < n; ++k) {
    const double z = 1 - (2 * k + 1.0) / n, r = std::sqrt(1 - z * z);
    out.emplace_back(r * std::cos(k * golden), r * std::sin(k * golden), z);
  }
  return out;
}

}  // namespace dualcell
