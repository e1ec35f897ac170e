#include "law/polar.hpp"

namespace dualcell::law {

PolarModuli polar_moduli(const std::function<double(double theta_deg, double sign)>& modulus) {
  constexpr int half = 180;
  PolarModuli out;
  for (int deg = 0; deg < half; ++deg) {
    out.deg.push_back(deg);
    out.E_tension.push_back(modulus(deg, 1));
    out.E_compression.push_back(modulus(deg, -1));
  }
  for (int deg = half; deg <= 2 * half; ++deg) {
    out.deg.push_back(deg);
    out.E_tension.push_back(out.E_tension[deg - half]);
    out.E_compression.push_back(out.E_compression[deg - half]);
  }
  return out;
}

}  // namespace dualcell::law
