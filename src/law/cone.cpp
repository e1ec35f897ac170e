#include "law/cone.hpp"

#include <Eigen/Cholesky>
#include <cmath>

namespace dualcell::law {

ConeState evaluate(const ConeLaw& law, const Eigen::Vector3d& strain) {
  ConeState s;
  const double opening = law.c.dot(strain);  // c·ε
  const double plus = std::max(opening, 0.0);
  s.plus_side = opening > 0;
  s.stress = law.C_c * strain + law.beta * plus * law.c;
  s.tangent = law.C_c;
  if (s.plus_side) s.tangent += law.beta * law.c * law.c.transpose();
  s.energy = 0.5 * strain.dot(law.C_c * strain) + 0.5 * law.beta * plus * plus;
  return s;
}

std::string admissibility_problem(const ConeLaw& law) {
  if (!law.C_c.allFinite() || !law.c.allFinite() || !std::isfinite(law.beta)) return "non-finite entries";
  if ((law.C_c - law.C_c.transpose()).norm() > 1e-12 * law.C_c.norm()) return "C_c is not symmetric";
  if (law.C_c.llt().info() != Eigen::Success) return "C_c is not positive definite";
  if (std::abs(law.c.norm() - 1) > 1e-12) return "c is not a unit vector";
  if (law.beta < 0) return "beta is negative";
  return "";
}

}  // namespace dualcell::law
