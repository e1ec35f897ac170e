// Newton's method on the structure's energy (docs/method.md §15): the energy, its gradient and
// one-sided tangent from the points' laws, and the damped Newton steps of one load factor.
#include <omp.h>

#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "core/error.hpp"
#include "fem/edge_conditions.hpp"
#include "fem/element.hpp"
#include "linalg/sparse_cholesky.hpp"
#include "structure/impl.hpp"
#include "structure/structure.hpp"

namespace dualcell::structure {

double HomogenisedStructure::Impl::energy(const Eigen::VectorXd& x, double factor, bool with_gradient,
                                          bool with_tangent) {
  evaluate_points(x);
  double Pi = -factor * f.dot(x);
  if (with_gradient) f_int.setZero();
  if (with_tangent) std::fill(K.valuePtr(), K.valuePtr() + K.nonZeros(), 0.0);
  const int n = 2 * per;
  Eigen::MatrixXd Ke(n, n);
  Eigen::VectorXd fe(n);
  for (Eigen::Index t = 0; t < mesh.triangles.rows(); ++t) {
    if (with_tangent) Ke.setZero();
    for (std::size_t k = 0; k < points[t].size(); ++k) {
      const Point& p = points[t][k];
      const law::ConeState& s = state[first_point[t] + k];
      Pi += p.weight * s.energy;
      if (with_gradient) {
        fe.noalias() = p.weight * (p.grad_s.transpose() * s.stress);
        for (int a = 0; a < n; ++a) f_int(dof(static_cast<int>(t), a)) += fe(a);
      }
      if (with_tangent) Ke.noalias() += p.weight * (p.grad_s.transpose() * s.tangent * p.grad_s);
    }
    if (with_tangent)
      for (int a = 0; a < n; ++a)
        for (int b = 0; b <= a; ++b) {
          const int k = slot[t][a * n + b];
          if (k >= 0) K.valuePtr()[k] += Ke(a, b);
        }
  }
  if (with_gradient) r_full = f_int - factor * f;
  return Pi;
}

void HomogenisedStructure::Impl::newton(double factor, StepResult& out) {
  Eigen::VectorXd r(n_free), delta(n_free);
  for (int d = 0; d < n_dofs; ++d)
    if (constrained_by[d] >= 0) u(d) = factor * prescribed(d);
  out.converged = false;
  double r_initial = 0;
  for (int iteration = 0; iteration <= scene.max_newton_steps; ++iteration) {
    const double Pi = energy(u, factor, true, true);
    for (int d = 0; d < n_dofs; ++d)
      if (free_index[d] >= 0) r(free_index[d]) = r_full(d);
    // Scale: the larger of the internal and the external forces (their sum is what equilibrium
    // balances), and the residual the step started from: prescribed displacements that a rigid
    // motion satisfies end in a stress-free state where both forces vanish, and only the
    // starting residual says what "small" is there.
    if (iteration == 0) r_initial = r.norm();
    const double scale = std::max({f_int.norm(), factor * f.norm(), r_initial, 1e-300});
    out.residual = r.norm() / scale;
    out.energy = Pi;
    if (progress)
      progress->update([&] {
        char text[200];
        std::snprintf(text, sizeof text, "load factor %g: Newton %d, residual %.1e (tol %.0e), %d fused cells, %s",
                      factor, iteration, out.residual, scene.tolerance, out.newly_fused_cells,
                      seconds_text(progress->seconds()).c_str());
        return std::string(text);
      });
    if (std::isfinite(Pi) && (out.residual <= scene.tolerance || n_free == 0)) {
      out.converged = true;
      return;
    }
    // A non-finite energy or residual (a load beyond the range of doubles) cannot come back to a
    // finite one: no further step can converge, so stop at the first one, not after
    // max_newton_steps line searches on NaN.
    if (!std::isfinite(Pi) || !std::isfinite(out.residual)) {
      if (out.message.empty()) out.message = "the energy or the residual is not finite";
      return;
    }
    if (iteration == scene.max_newton_steps) break;
    if (cholesky.factorize(K) != linalg::CholeskyStatus::ok)
      throw InputError(
          "the structure's tangent is not positive definite: the edges and supports do not hold it "
          "against every rigid-body motion (give a [[support]] or a fixed, roller or displacement edge)");
    cholesky.solve(-r, delta);
    // Backtracking (Armijo) on Π: the full step is exact once every element's open planes are
    // right. Near the solution the decrease a step promises, t·|rᵀδ|, falls below the round-off
    // of Π itself (Π is a sum of terms of size |fᵀu|, each rounded): Π can no longer tell a good
    // step from a bad one there, and the step is judged by the residual instead (‖r‖ must fall),
    // which Newton's method on the piecewise-linear gradient does once the open sets settle.
    const double slope = r.dot(delta);
    const double noise = 64 * std::numeric_limits<double>::epsilon() * (std::abs(Pi) + std::abs(factor * f.dot(u)));
    const double r_norm = r.norm();
    const auto set_trial = [&](double t) {
      for (int d = 0; d < n_dofs; ++d)
        if (free_index[d] >= 0) trial(d) = u(d) + t * delta(free_index[d]);
    };
    const auto trial_residual = [&] {
      energy(trial, factor, true, false);
      double sum = 0;
      for (int d = 0; d < n_dofs; ++d)
        if (free_index[d] >= 0) sum += r_full(d) * r_full(d);
      return std::sqrt(sum);
    };
    double t = 1;
    trial = u;
    for (;;) {
      set_trial(t);
      if (energy(trial, factor, false, false) <= Pi + 1e-4 * t * slope) break;
      if (-t * slope <= noise) {
        for (t = 1; t >= 1e-12; t /= 2) {
          set_trial(t);
          if (trial_residual() <= (1 - 1e-4 * t) * r_norm) break;
        }
        break;
      }
      if (t < 1e-12) break;
      t /= 2;
    }
    u = trial;
    ++out.newton_steps;
  }
}

}  // namespace dualcell::structure
