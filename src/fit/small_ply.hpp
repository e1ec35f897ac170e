#pragma once
// The small cell as the whole ply's compact law (docs/method.md §16e): the strain and the shears
// along the fibres added to a small cell fitted in the plane (fit/small_cell.hpp).
//
// A small cell's rows are contact rows: past the fuse, or without adhesion, no bond is left, so
// its shear along the fibres is the open cell's, τ = D0z Γ, exactly as the exact law's is without
// bonds. Its strain along the fibres needs the rows' opening per unit ε33, y33 (m numbers; A33 and
// C33 are the open cell's, which the small cell shares). With D and M held (the in-plane fit), the
// strain-driven law at (ε̄, ε33) is
//   μ = argmin over μ ≥ 0 of ½ μᵀMμ − μᵀ(D ε̃ + y33 ε33),   ε̃ = ε̄ − A33 ε33,
//   σ̄ = C₀ ε̃ + Dᵀμ/|Ω|,   σ33 = −A33·σ̄ + C33 ε33 + y33·μ/|Ω|,
// so on the free set F of a point μ_F = M_FF⁻¹(D_F ε̃ + y33_F ε33), and with W = ε33 M_FF⁻¹
//   ∂σ̄/∂y33_F = D_Fᵀ W/|Ω|,   ∂σ33/∂y33_F = −A33ᵀ ∂σ̄/∂y33_F + (μ_F + W y33_F)ᵀ/|Ω|.
// y33 minimises Σ_i |(σ̄, σ33)(ε_i) − (σ̄_i, σ33_i)|²/|σ_i|² over the exact law's points (σ_i the
// six stresses): Levenberg–Marquardt from y33 = 0 with that Jacobian.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "law/condensed.hpp"
#include "law/ply_sample.hpp"

namespace dualcell::fit {

struct SmallPlyFit {
  bool ok = false;
  std::string message;
  int points = 0, iterations = 0;
  double training_max_error = 0, training_rms_error = 0;  // of the six stresses, relative
};

// Gives `small` (contact rows only, no equality rows) the strain along the fibres of `cell` (A33,
// C33; y33 fitted to the exact points) and its open shear (shear = 2, D0z, no shear rows); `cell`
// must carry the whole ply (longitudinal = 1, shear = 2).
SmallPlyFit fit_small_ply(law::CondensedCell& small, const law::CondensedCell& cell,
                          const std::vector<law::Vector6d>& strain, const std::vector<law::Vector6d>& stress);

// The fit's residuals (4 per point: σ̄ and σ33 over |σ_i|) at y33 = y, and their Jacobian (4·points
// × m) when J is given; false where the cell cannot be evaluated. Exposed so that the closed form
// can be checked against differences.
bool small_ply_residuals(const law::CondensedCell& small, const Eigen::VectorXd& y,
                         const std::vector<law::Vector6d>& strain, const std::vector<law::Vector6d>& stress,
                         Eigen::VectorXd& f, Eigen::MatrixXd* J);

}  // namespace dualcell::fit
