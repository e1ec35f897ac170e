#pragma once
// The cone-wise linear law (Curnier, He & Zysset, J. Elasticity 37, 1995; docs/method.md §14):
// one strain energy for every strain, in the engineering-shear strain space ε = (εxx, εyy, γxy),
//
//   W(ε) = ½ εᵀ C_c ε + ½ β ⟨c·ε⟩₊²,        ⟨x⟩₊ = max(x, 0),
//   σ(ε) = ∂W/∂ε = C_c ε + β ⟨c·ε⟩₊ c,      (σxx, σyy, σxy)
//   C(ε) = ∂σ/∂ε = C_c + β H(c·ε) c cᵀ    (H the Heaviside step; off the plane c·ε = 0),
//
// with C_c symmetric positive definite, c a unit normal of the switching plane and β ≥ 0: the
// stiffness is C_c on the side c·ε ≤ 0 and C_c + β c cᵀ on the side c·ε > 0. W is then convex
// and C¹ (σ continuous across the plane), so a structure code can use it for every strain. For a
// cell softer in tension than in compression the fitted c points into compression (c·ε > 0
// under uniaxial compression).
#include <Eigen/Core>
#include <string>
#include <vector>

namespace dualcell::law {

struct ConeLaw {
  Eigen::Matrix3d C_c = Eigen::Matrix3d::Identity();  // stiffness where c·ε ≤ 0
  Eigen::Vector3d c = Eigen::Vector3d::UnitX();       // unit normal of the switching plane
  double beta = 0;                                    // β ≥ 0: the jump of stiffness across it
};

struct ConeState {
  Eigen::Vector3d stress;   // σ(ε)
  Eigen::Matrix3d tangent;  // consistent tangent: C_c, plus β c cᵀ where c·ε > 0
  double energy = 0;        // W(ε)
  bool plus_side = false;   // c·ε > 0 (the stiffer side)
};

// A cone-wise law fitted to stress–strain points (fit/cone_fit.hpp), with its quality.
struct ConeFit {
  ConeLaw law;
  double relative_residual = 0;            // sqrt(mean over points of |σ(ε_i) − σ_i|²/|σ_i|²)
  std::vector<double> direction_residual;  // the same per load direction (NaN: no point there)
  int n_points = 0;
  bool ok = false;      // enough points (≥ 3) and a finite, admissible fit
  std::string message;  // why not, when not ok
};

// Stress, consistent tangent, energy and side of the law at strain ε (engineering shear).
ConeState evaluate(const ConeLaw& law, const Eigen::Vector3d& strain);

// Empty when the law is admissible (C_c symmetric positive definite, |c| = 1 to 1e-12, β ≥ 0,
// everything finite); otherwise what is wrong.
std::string admissibility_problem(const ConeLaw& law);

}  // namespace dualcell::law
