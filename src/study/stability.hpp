#pragma once
// The stability matrix (docs/results/stability.md): the solver run
// for both element orders over stiffness contrasts E_f/E_m ∈ {1e-6, 1e-3, 1, 1e3, 1e6}, matrix Poisson ratios ν_m ∈ {0,
// 0.3, 0.45, 0.499}, fibre sizes r/a ∈ {0.05, 0.3, 0.45} and an off-centre fibre next to the cell edge, adhesion none /
// tiny / huge, load magnitudes from 1e-12 to 1e6 (units of E_m), directions 0°, 30°, 45°, 90° and the three boundary
// conditions. Every case must either converge with its KKT residuals below tolerance and its primal check passed, or
// stop with a diagnostic; a NaN or Inf in a result that claims convergence is a failure.
#include <filesystem>
#include <string>
#include <vector>

#include "core/scene.hpp"

namespace dualcell::study {

struct StabilityCase {
  Boundary boundary = Boundary::periodic;
  double direction_deg = 0;
  double stiffness_ratio = 1;  // E_f / E_m (E_m = 1)
  double nu_matrix = 0.3;
  double radius = 0.3;            // cell size 1
  double offset = 0;              // along x
  std::string adhesion = "none";  // none, tiny (strength 1e-6), huge (1e6)
  double load = 1;                // signed magnitude s, σ̄ = s n⊗n
  int degree = 2;
  Element element = Element::p1;
};

struct StabilityRow {
  StabilityCase c;
  std::string status;  // of the QP
  bool primal_ok = false;
  bool finite = false;  // u, λ, strain all finite
  bool ok = false;      // converged, checked and finite, or stopped with a diagnostic
  std::string message;
  long outer_iterations = 0, operator_applications = 0;
  double relative_projected_gradient = 0, relative_equality_residual = 0, relative_equilibrium = 0;
  double penetration = 0, glue_jump = 0;  // relative to ‖u‖∞
  int broken = 0;
  double modulus = 0;  // s / ε_nn
  double seconds = 0;
};

// The full matrix (`fast`: a subset of ~100 cases for the test suite).
std::vector<StabilityCase> stability_cases(bool fast);
StabilityRow run_stability_case(const StabilityCase& c, double tolerance = 1e-8);

// The whole matrix (or the fast subset) written as a CSV, one row per case, and a Markdown
// summary per factor value (both atomically); progress on stderr when asked.
struct StabilityOptions {
  std::filesystem::path csv, summary;  // summary may be empty
  bool fast = false;
  double tolerance = 1e-8;
  bool progress = false;
};
struct StabilityReport {
  int cases = 0, failed = 0;  // failed: a silent NaN/Inf, or a stop without a diagnostic
  int stopped = 0;            // stopped with a diagnostic instead of converging
};
StabilityReport run_stability(const StabilityOptions& options);

}  // namespace dualcell::study
