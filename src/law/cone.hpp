#pragma once
// The cone-wise linear law (docs/method.md §14),
// with one or more switching planes: one strain energy for every strain, in the
// engineering-shear strain space ε = (εxx, εyy, γxy),
//
//   W(ε) = ½ εᵀ C_c ε + ½ Σ_k β_k ⟨q_k·ε⟩₊²,        ⟨x⟩₊ = max(x, 0),
//   σ(ε) = ∂W/∂ε = C_c ε + Σ_k β_k ⟨q_k·ε⟩₊ q_k,      (σxx, σyy, σxy)
//   C(ε) = ∂σ/∂ε = C_c + Σ_k β_k H(q_k·ε) q_k q_kᵀ    (H the Heaviside step; off the planes),
//
// with C_c symmetric positive definite, unit normals q_k and β_k ≥ 0. Each term is convex and
// C¹, so W is convex and C¹ (σ continuous across every plane) and a structure code can use it
// for every strain. The original form (docs/method.md §14) is one plane (K = 1): stiffness C_c where
// q·ε ≤ 0 and C_c + β q qᵀ where q·ε > 0. Several planes q_k = −n_k⊗n_k (compression struts
// along in-plane directions n_k) describe a cell whose gaps close under compression along n_k
// whatever the other strains do.
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "law/polar.hpp"

namespace dualcell::law {

// At most this many planes (the open ones of a strain fit in a 32-bit mask).
inline constexpr int max_planes = 32;

struct ConeLaw {
  Eigen::Matrix3d C_c = Eigen::Matrix3d::Identity();            // stiffness where every q_k·ε ≤ 0
  std::vector<Eigen::Vector3d> q = {Eigen::Vector3d::UnitX()};  // unit normals q_k of the switching planes
  // β_k ≥ 0: the stiffness added across plane k, C(ε) = C_c + Σ β_k q_k q_kᵀ over the open planes
  std::vector<double> beta = {0.0};
};

struct ConeState {
  Eigen::Vector3d stress;   // σ(ε)
  Eigen::Matrix3d tangent;  // consistent tangent: C_c, plus β_k q_k q_kᵀ for every open plane
  double energy = 0;        // W(ε)
  std::uint32_t open = 0;   // bit k set where q_k·ε > 0 (the stiffer side of plane k)
};

// A cone-wise law fitted to stress–strain points (fit/cone_fit.hpp), with its quality.
struct ConeFit {
  ConeLaw law;
  std::string form;                        // "one plane" or "compression struts" (law/cone.hpp), the better of the two
  double relative_residual = 0;            // sqrt(mean over points of |σ(ε_i) − σ_i|²/|σ_i|²)
  std::vector<double> direction_residual;  // the same per load direction (NaN: no point there)
  int n_points = 0;
  bool ok = false;      // enough points (≥ 3) and a finite, admissible fit
  std::string message;  // why not, when not ok
  // The relative residual of each form tried (NaN where that form gave no admissible law).
  double one_plane_residual = 0, struts_residual = 0;
  // When ok: the law's apparent moduli around the circle (polar_moduli of apparent_modulus).
  PolarModuli polar;
};

// The apparent moduli of the law around the circle, for ConeFit::polar.
PolarModuli cone_polar(const ConeLaw& law);

// Stress, consistent tangent, energy and side of the law at strain ε (engineering shear).
ConeState evaluate(const ConeLaw& law, const Eigen::Vector3d& strain);

// Empty when the law is admissible (1 to max_planes planes, as many β as q, C_c symmetric
// positive definite, every |q_k| = 1 to 1e-12, every β_k ≥ 0, everything finite); otherwise
// what is wrong.
std::string admissibility_problem(const ConeLaw& law);

// The strain at which the law carries the stress σ̄: the minimiser of the convex W(ε) − σ̄·ε, by
// Newton's method with the one-sided tangent and a backtracking line search on that energy
// (finitely many steps for a piecewise quadratic). Exact to round-off: ‖σ(ε) − σ̄‖ ≤ 1e-13‖σ̄‖.
Eigen::Vector3d strain_for(const ConeLaw& law, const Eigen::Vector3d& stress);

// The law's apparent plane-strain modulus E = s/ε_nn under the uniaxial stress s·n⊗n along
// n = (cos θ, sin θ), in tension (sign +1) or compression (−1): what the sweep measures per
// direction, so that the two can be set side by side.
double apparent_modulus(const ConeLaw& law, double theta_deg, double sign);

}  // namespace dualcell::law
