// Kernels on the box Ω = {x : l ≤ x ≤ u} shared by MPRGP and SMALBE: projection, feasible step,
// the free/chopped split of the gradient and the KKT residuals of a returned point.
// Entries of l may be -inf and of u +inf, so lower-only, upper-only and box bounds are one case.
//
// Definitions (docs/method.md §7 and §17, extended to upper bounds), for feasible x and g = A x - b:
//   free set      F = {i : l_i < x_i < u_i}
//   φ_i  (free gradient)     = g_i on F, 0 otherwise
//   ψ_i  (chopped gradient, β in the papers of docs/method.md §18)
//                            = min(g_i, 0) at a lower bound, max(g_i, 0) at an upper bound,
//                              0 on F and where l_i = u_i (a fixed component)
//   gᴾ   (projected gradient) = φ + ψ; x is a KKT point iff gᴾ = 0
//   φ̃_i  (reduced free gradient, for steplength ω̄) = min((x_i - l_i)/ω̄, g_i) if g_i > 0,
//                              max((x_i - u_i)/ω̄, g_i) if g_i < 0, on F
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <string>

#include "qp/result.hpp"

namespace dualcell::qp {

struct GradientSplit {
  double phi_norm2 = 0;          // ‖φ‖²
  double psi_norm2 = 0;          // ‖ψ‖²
  double phi_tilde_dot_phi = 0;  // φ̃ᵀφ, the right side of the proportioning test
  double projected_norm() const { return std::sqrt(phi_norm2 + psi_norm2); }
};

// Writes φ and ψ (pre-sized) for feasible x and returns their norms and φ̃ᵀφ.
GradientSplit split_gradient(const Eigen::VectorXd& x, const Eigen::VectorXd& g, const Eigen::VectorXd& l,
                             const Eigen::VectorXd& u, double omega_bar, Eigen::VectorXd& phi, Eigen::VectorXd& psi);

// v_i ← 0 outside the free set F of feasible x (v ← χ_F ⊙ v).
void restrict_to_free_set(const Eigen::VectorXd& x, const Eigen::VectorXd& l, const Eigen::VectorXd& u,
                          Eigen::VectorXd& v);

// ‖gᴾ‖ without work vectors.
double projected_gradient_norm(const Eigen::VectorXd& x, const Eigen::VectorXd& g, const Eigen::VectorXd& l,
                               const Eigen::VectorXd& u);

// x ← P_Ω(x), componentwise clamp.
void project_onto_box(const Eigen::VectorXd& l, const Eigen::VectorXd& u, Eigen::VectorXd& x);

// Largest step length ω ≥ 0 with l ≤ x - ω d ≤ u (ω_f in mprgp.cpp), and the component that
// blocks it (blocking = -1 and ω = +inf when no finite bound lies in the direction -d).
struct FeasibleStep {
  double omega;
  Eigen::Index blocking;
};
FeasibleStep max_feasible_step(const Eigen::VectorXd& x, const Eigen::VectorXd& d, const Eigen::VectorXd& l,
                               const Eigen::VectorXd& u);

// x ← x - ω d for ω ≤ the feasible step `limit` (asserted): the blocking component is put exactly
// on its bound when ω reaches it, and a final clamp removes round-off, so x never leaves Ω.
void step_within_box(double omega, const Eigen::VectorXd& d, const FeasibleStep& limit, const Eigen::VectorXd& l,
                     const Eigen::VectorXd& u, Eigen::VectorXd& x);

// Empty when b, l, u (and x unless empty) are consistent: equal sizes, no NaN, b finite,
// l < +inf, u > -inf, l ≤ u, x finite. Otherwise a one-line description of the first problem.
std::string check_bound_problem(const Eigen::VectorXd& b, const Eigen::VectorXd& l, const Eigen::VectorXd& u,
                                const Eigen::VectorXd& x);

// Fills projected_gradient_norm, relative_projected_gradient (= ‖gᴾ‖/scale), bound_violation and
// complementarity of `result` from x and its (Lagrangian) gradient g.
void fill_bound_residuals(const Eigen::VectorXd& x, const Eigen::VectorXd& g, const Eigen::VectorXd& l,
                          const Eigen::VectorXd& u, double scale, Result& result);

// Marks every residual of `result` as not computed (NaN).
void clear_residuals(Result& result);

}  // namespace dualcell::qp
