#pragma once
// A law's apparent plane-strain moduli around the circle (law.hpp's convention): E(θ) = s/ε_nn
// under the uniaxial stress ±s·n⊗n, n = (cos θ, sin θ), in tension and in compression. The one
// function every curve of the polar picture comes from (the compact law's, the exact law's);
// the fit computes and stores them, the writers write them.
#include <functional>
#include <vector>

namespace dualcell::law {

struct PolarModuli {
  std::vector<double> deg, E_tension, E_compression;  // θ = 0, 1, …, 360°; NaN where undetermined
  bool empty() const { return deg.empty(); }
};

// `modulus(θ_deg, sign)`: the apparent modulus of the law under sign·n⊗n (sign +1 tension, −1
// compression), NaN where it cannot tell. n⊗n is the same at θ and θ + 180°, so the law is
// evaluated at θ = 0, …, 179° only and the other half of the circle repeats those values.
PolarModuli polar_moduli(const std::function<double(double theta_deg, double sign)>& modulus);

}  // namespace dualcell::law
