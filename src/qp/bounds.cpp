#include "qp/bounds.hpp"

#include <algorithm>
#include <cassert>
#include <limits>
#include <sstream>

namespace dualcell::qp {

namespace {
constexpr double infinity = std::numeric_limits<double>::infinity();
}

GradientSplit split_gradient(const Eigen::VectorXd& x, const Eigen::VectorXd& g, const Eigen::VectorXd& l,
                             const Eigen::VectorXd& u, double omega_bar, Eigen::VectorXd& phi, Eigen::VectorXd& psi) {
  GradientSplit split;
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    const bool at_lower = x[i] <= l[i];
    const bool at_upper = x[i] >= u[i];
    if (!at_lower && !at_upper) {
      phi[i] = g[i];
      psi[i] = 0.0;
      // φ̃ caps the free gradient by the distance to the bound it points at, over ω̄.
      const double phi_tilde =
          g[i] > 0.0 ? std::min((x[i] - l[i]) / omega_bar, g[i]) : std::max((x[i] - u[i]) / omega_bar, g[i]);
      split.phi_norm2 += g[i] * g[i];
      split.phi_tilde_dot_phi += phi_tilde * g[i];
    } else {
      phi[i] = 0.0;
      if (at_lower && at_upper) {
        psi[i] = 0.0;
      } else {
        psi[i] = at_lower ? std::min(g[i], 0.0) : std::max(g[i], 0.0);
        split.psi_norm2 += psi[i] * psi[i];
      }
    }
  }
  return split;
}

void restrict_to_free_set(const Eigen::VectorXd& x, const Eigen::VectorXd& l, const Eigen::VectorXd& u,
                          Eigen::VectorXd& v) {
  // The same test for "free" as split_gradient, so that z and φ share their support.
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    if (x[i] <= l[i] || x[i] >= u[i]) {
      v[i] = 0.0;
    }
  }
}

double projected_gradient_norm(const Eigen::VectorXd& x, const Eigen::VectorXd& g, const Eigen::VectorXd& l,
                               const Eigen::VectorXd& u) {
  double sum = 0.0;
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    const bool at_lower = x[i] <= l[i];
    const bool at_upper = x[i] >= u[i];
    double gp = g[i];
    if (at_lower && at_upper) {
      gp = 0.0;
    } else if (at_lower) {
      gp = std::min(g[i], 0.0);
    } else if (at_upper) {
      gp = std::max(g[i], 0.0);
    }
    sum += gp * gp;
  }
  return std::sqrt(sum);
}

void project_onto_box(const Eigen::VectorXd& l, const Eigen::VectorXd& u, Eigen::VectorXd& x) {
  x = x.cwiseMax(l).cwiseMin(u);
}

FeasibleStep max_feasible_step(const Eigen::VectorXd& x, const Eigen::VectorXd& d, const Eigen::VectorXd& l,
                               const Eigen::VectorXd& u) {
  FeasibleStep step{infinity, -1};
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    double omega = infinity;
    if (d[i] > 0.0) {
      omega = (x[i] - l[i]) / d[i];
    } else if (d[i] < 0.0) {
      omega = (x[i] - u[i]) / d[i];
    }
    if (omega < step.omega) {
      step = {omega, i};
    }
  }
  return step;
}

void step_within_box(double omega, const Eigen::VectorXd& d, const FeasibleStep& limit, const Eigen::VectorXd& l,
                     const Eigen::VectorXd& u, Eigen::VectorXd& x) {
  // A longer step would be a logic error, which the clamp below must not hide.
  assert(omega <= limit.omega);
  x -= omega * d;
  if (limit.blocking >= 0 && omega >= limit.omega) {
    const Eigen::Index i = limit.blocking;
    x[i] = d[i] > 0.0 ? l[i] : u[i];
  }
  project_onto_box(l, u, x);
}

std::string check_bound_problem(const Eigen::VectorXd& b, const Eigen::VectorXd& l, const Eigen::VectorXd& u,
                                const Eigen::VectorXd& x) {
  const Eigen::Index n = b.size();
  if (l.size() != n || u.size() != n || (x.size() != 0 && x.size() != n)) {
    std::ostringstream out;
    out << "size mismatch: b has " << n << " entries, l " << l.size() << ", u " << u.size() << ", x " << x.size();
    return out.str();
  }
  // Scan first and format only on failure: SMALBE calls this once per outer iteration.
  Eigen::Index i = 0;
  while (i < n && std::isfinite(b[i]) && !std::isnan(l[i]) && !std::isnan(u[i]) && l[i] < infinity &&
         u[i] > -infinity && l[i] <= u[i] && (x.size() == 0 || std::isfinite(x[i]))) {
    ++i;
  }
  if (i == n) {
    return {};
  }
  std::ostringstream out;
  if (!std::isfinite(b[i])) {
    out << "b[" << i << "] = " << b[i] << " is not finite";
  } else if (std::isnan(l[i]) || std::isnan(u[i])) {
    out << "bound " << i << " is NaN";
  } else if (l[i] == infinity || u[i] == -infinity) {
    out << "bound " << i << " makes the feasible set empty: l = " << l[i] << ", u = " << u[i];
  } else if (l[i] > u[i]) {
    out << "l[" << i << "] = " << l[i] << " > u[" << i << "] = " << u[i];
  } else {
    out << "initial guess x[" << i << "] = " << x[i] << " is not finite";
  }
  return out.str();
}

void fill_bound_residuals(const Eigen::VectorXd& x, const Eigen::VectorXd& g, const Eigen::VectorXd& l,
                          const Eigen::VectorXd& u, double scale, Result& result) {
  double violation = 0.0;
  double complementarity = 0.0;
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    violation = std::max({violation, l[i] - x[i], x[i] - u[i]});
    // A positive g_i must be held by the lower bound, a negative one by the upper bound.
    if (std::isfinite(l[i])) {
      complementarity = std::max(complementarity, std::max(g[i], 0.0) * (x[i] - l[i]));
    }
    if (std::isfinite(u[i])) {
      complementarity = std::max(complementarity, std::max(-g[i], 0.0) * (u[i] - x[i]));
    }
  }
  result.projected_gradient_norm = projected_gradient_norm(x, g, l, u);
  result.relative_projected_gradient = result.projected_gradient_norm / scale;
  result.bound_violation = violation;
  result.complementarity = complementarity;
}

void clear_residuals(Result& result) {
  constexpr double not_computed = std::numeric_limits<double>::quiet_NaN();
  result.projected_gradient_norm = not_computed;
  result.relative_projected_gradient = not_computed;
  result.equality_residual = not_computed;
  result.bound_violation = not_computed;
  result.complementarity = not_computed;
}

}  // namespace dualcell::qp
