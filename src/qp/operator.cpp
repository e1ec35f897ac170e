#include "qp/operator.hpp"

#include <cmath>
#include <random>

namespace dualcell::qp {

double estimate_norm(const LinearOperator& A, Eigen::Index n, int iterations, unsigned seed) {
  if (n <= 0 || iterations < 1) {
    return 0.0;
  }
  // Safety factor over the power-iteration value, which is a lower bound of ‖A‖.
  constexpr double safety = 1.01;

  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Eigen::VectorXd v(n);
  Eigen::VectorXd w(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    v[i] = uniform(rng);
  }
  v /= v.norm();

  double estimate = 0.0;
  for (int k = 0; k < iterations; ++k) {
    A(v, w);
    estimate = w.norm();
    if (!std::isfinite(estimate) || estimate == 0.0) {
      return estimate;
    }
    v = w / estimate;
  }
  return safety * estimate;
}

}  // namespace dualcell::qp
