#include "fit/levenberg_marquardt.hpp"

#include <Eigen/Cholesky>
#include <algorithm>

namespace dualcell::fit {

LmEnd levenberg_marquardt(const Residuals& residuals, Eigen::Index n, Eigen::VectorXd& x, const LmStop& stop,
                          const std::function<void(int)>& step) {
  const Eigen::Index p = x.size();
  Eigen::VectorXd f(n), trial_f(n), g(p), scale(p), candidate(p);
  Eigen::MatrixXd J(n, p), A(p, p), B(p, p);
  LmEnd end;
  if (!residuals(x, f, &J)) return end;
  end.evaluated = true;
  double cost = f.squaredNorm(), lambda = 1e-3;
  int quiet = 0;  // accepted steps in a row that lowered the cost by less than quiet_fraction of it
  for (int it = 0; it < stop.max_iterations && quiet < stop.quiet_steps; ++it, ++end.iterations) {
    if (step) step(it);
    A.setZero();
    A.selfadjointView<Eigen::Lower>().rankUpdate(J.transpose());
    g.noalias() = J.transpose() * f;
    scale = A.diagonal().cwiseMax(1e-12 * A.diagonal().maxCoeff());
    bool accepted = false;
    for (int tries = 0; tries < 20 && !accepted; ++tries) {
      B = A;
      B.diagonal() += lambda * scale;
      const Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>, Eigen::Lower> llt(B);  // in place
      if (llt.info() != Eigen::Success) {
        lambda *= 4;
        continue;
      }
      candidate = x - llt.solve(g);
      if (residuals(candidate, trial_f, nullptr) && trial_f.squaredNorm() < cost) {
        const double trial_cost = trial_f.squaredNorm();
        quiet = cost - trial_cost < stop.quiet_fraction * cost ? quiet + 1 : 0;
        x.swap(candidate);
        cost = trial_cost;
        lambda = std::max(lambda / 3, 1e-12);
        accepted = true;
      } else {
        lambda *= 4;
      }
    }
    if (!accepted) break;
    residuals(x, f, &J);
  }
  return end;
}

}  // namespace dualcell::fit
