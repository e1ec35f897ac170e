#include "law/cone.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/directions.hpp"

namespace dualcell::law {

ConeState evaluate(const ConeLaw& law, const Eigen::Vector3d& strain) {
  ConeState s;
  s.stress = law.C_c * strain;
  s.tangent = law.C_c;
  s.energy = 0.5 * strain.dot(s.stress);
  for (std::size_t k = 0; k < law.q.size(); ++k) {
    const double opening = law.q[k].dot(strain);  // q_k·ε
    if (opening <= 0) continue;
    s.open |= std::uint32_t{1} << k;
    s.stress += law.beta[k] * opening * law.q[k];
    s.tangent += law.beta[k] * law.q[k] * law.q[k].transpose();
    s.energy += 0.5 * law.beta[k] * opening * opening;
  }
  return s;
}

std::string admissibility_problem(const ConeLaw& law) {
  if (law.q.empty() || law.q.size() > static_cast<std::size_t>(max_planes))
    return "the number of planes is " + std::to_string(law.q.size()) + ", not 1 to " + std::to_string(max_planes);
  if (law.beta.size() != law.q.size()) return "there are not as many beta as planes";
  if (!law.C_c.allFinite()) return "non-finite entries";
  for (std::size_t k = 0; k < law.q.size(); ++k)
    if (!law.q[k].allFinite() || !std::isfinite(law.beta[k])) return "non-finite entries";
  if ((law.C_c - law.C_c.transpose()).norm() > 1e-12 * law.C_c.norm()) return "C_c is not symmetric";
  if (law.C_c.llt().info() != Eigen::Success) return "C_c is not positive definite";
  for (std::size_t k = 0; k < law.q.size(); ++k) {
    if (std::abs(law.q[k].norm() - 1) > 1e-12) return "q is not a unit vector";
    if (law.beta[k] < 0) return "beta is negative";
  }
  return "";
}

Eigen::Vector3d strain_for(const ConeLaw& law, const Eigen::Vector3d& stress) {
  // Π(ε) = W(ε) − σ̄·ε is convex and piecewise quadratic; its gradient is σ(ε) − σ̄.
  const auto Pi = [&](const Eigen::Vector3d& e) { return evaluate(law, e).energy - stress.dot(e); };
  Eigen::Vector3d e = law.C_c.llt().solve(stress);
  const double target = 1e-14 * stress.norm();
  for (int iteration = 0; iteration < 100; ++iteration) {
    const ConeState s = evaluate(law, e);
    const Eigen::Vector3d r = s.stress - stress;
    if (r.norm() <= target) break;
    const Eigen::Vector3d step = -s.tangent.llt().solve(r);
    // Backtracking (Armijo) on Π: the full step is exact once the open set is right.
    const double slope = r.dot(step), now = Pi(e);
    double t = 1;
    while (t > 1e-12 && Pi(e + t * step) > now + 1e-4 * t * slope) t /= 2;
    e += t * step;
  }
  return e;
}

double apparent_modulus(const ConeLaw& law, double theta_deg, double sign) {
  const Eigen::Vector3d n = uniaxial_stress(theta_deg * std::numbers::pi / 180);
  const Eigen::Vector3d e = strain_for(law, sign * n);
  return sign / (n(0) * e(0) + n(1) * e(1) + n(2) * e(2));
}

PolarModuli cone_polar(const ConeLaw& law) {
  return polar_moduli([&](double theta_deg, double sign) { return apparent_modulus(law, theta_deg, sign); });
}

}  // namespace dualcell::law
