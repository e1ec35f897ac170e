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
//     (C_c, β), so a least-squares problem with β ≥ 0 (docs/method.md §14), tried with at least 7
//     distinct strain directions and kept only where C_c is positive definite.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "law/condensed.hpp"
#include "law/cone.hpp"
#include "law/cone_check.hpp"

namespace dualcell::fit {

struct ConePoint {
  Eigen::Vector3d strain;  // (εxx, εyy, γxy), engineering shear
  Eigen::Vector3d stress;  // (σxx, σyy, σxy)
  int direction = 0;       // index of the load direction it belongs to (for per-direction residuals)
};

// Fits the law to `points`; `guess` (any vector, normalised here; zero for none) adds a start for q.
law::ConeFit fit_cone(const std::vector<ConePoint>& points, int n_directions,
                      const Eigen::Vector3d& guess = Eigen::Vector3d::Zero());

// The cone-wise law fitted to the exact law (law/condensed.hpp) instead of the sweep: sampled at
// n stress directions over the whole sphere (law::sample_cell; a different set from the check's),
// with C_c the open cell's stiffness S₀⁻¹ (every interface row removed: the softest state), fixed
// candidate planes q_k at 240 directions spread over the unit sphere of strains and β ≥ 0 by
// nonnegative least squares: positive definite and convex by construction, linear in β. The
// cell's symmetries among the square's eight are measured on the exact law; the sample is
// augmented by its images and the planes of one orbit share their β, so the law has the cell's
// symmetries exactly. The orbits with the largest β are kept, at most law::max_planes planes,
// and refitted. Its residuals (relative_residual, direction_residual) are over the sweep's
// `points`, as fit_cone's are; form "planes fitted to the exact law, N symmetries of the cell".
// Not ok where no admissible law results. `past_fuse`: the same fitted to the exact law past the
// fuse (law::sample_cell_past_fuse at n directions, or `past_fuse_sample` where given), for
// Law::cone_after_fuse. `symmetries`: the cell's (cell_symmetries), where the caller has them.
enum class Fitted { bonded, past_fuse };
law::ConeFit fit_cone_to_cell(const law::CondensedCell& cell, const std::vector<ConePoint>& points, int n_directions,
                              Fitted fitted = Fitted::bonded, int n = 800,
                              const law::CellSample* past_fuse_sample = nullptr,
                              const std::vector<Eigen::Matrix3d>* symmetries = nullptr);

// The symmetries of a cell that its exact law shows at the states of `sample` (law::sample_cell),
// among the eight of the square (reflections x → −x and y → −y, which flip γxy and σxy, and the
// swap x ↔ y, with their products), as matrices on (εxx, εyy, γxy) that act on (σxx, σyy, σxy)
// the same way, the identity first; the identity alone for a cell without shear (n_macro = 2).
std::vector<Eigen::Matrix3d> cell_symmetries(const law::CondensedCell& cell, const law::CellSample& sample);

}  // namespace dualcell::fit
