#pragma once
// The cone-wise linear law fitted to stress–strain points (law/cone.hpp, docs/method.md §14),
// minimising the residuals r_i = (σ(ε_i) − σ_i)/|σ_i| (every point weighs alike) in two forms,
// each admissible by construction, keeping the one with the smaller residual:
//   one plane: GSL gsl_multifit_nlinear (trust region, finite-difference Jacobian) over
//     C_c = L Lᵀ, L lower triangular with diagonal exp(p₀), exp(p₂), exp(p₅)   (SPD),
//     q   = (sin p₆ cos p₇, sin p₆ sin p₇, cos p₆)                              (unit),
//     β   = p₈²                                                                  (≥ 0);
//     not convex in q (the kink of ⟨q·ε⟩₊ moves with it), so it starts from the linear fit C₀
//     of all points with q at each of 64 points spread over the unit sphere (and the guess);
//   compression struts: fixed planes q_k = −n_k⊗n_k/|n_k⊗n_k| at θ_k = k·15°; σ is linear in
//     (C_c, β), so a least-squares problem with β ≥ 0 (Lawson–Hanson), tried with at least 7
//     distinct strain directions and kept only where C_c is positive definite.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "law/cone.hpp"

namespace dualcell::fit {

struct ConePoint {
  Eigen::Vector3d strain;  // (εxx, εyy, γxy), engineering shear
  Eigen::Vector3d stress;  // (σxx, σyy, σxy)
  int direction = 0;       // index of the load direction it belongs to (for per-direction residuals)
};

// Fits the law to `points`; `guess` (any vector, normalised here; zero for none) adds a start for q.
law::ConeFit fit_cone(const std::vector<ConePoint>& points, int n_directions,
                      const Eigen::Vector3d& guess = Eigen::Vector3d::Zero());

}  // namespace dualcell::fit
