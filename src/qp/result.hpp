// How a QP solve ended: status, step counters and the KKT residuals of the returned point.
#pragma once

#include <string>

#include "core/fields.hpp"

namespace dualcell::qp {

enum class Status {
  converged,       // the stopping test holds on a freshly computed gradient
  max_iterations,  // iteration or operator-application budget exhausted
  stagnated,       // no progress (objective or ‖gᴾ‖) over a window of steps: tolerance too tight
  invalid_input,   // sizes, NaN, l > u or options; x is left unchanged
  non_finite,      // the operator produced NaN/Inf; x is the last finite feasible iterate
  unbounded,       // a direction of zero curvature along which the objective decreases forever
};

const char* to_string(Status status);

struct Counters {
  long cg_steps = 0;
  long expansion_steps = 0;
  long proportioning_steps = 0;
  long operator_applications = 0;        // applications of the caller's A (incl. norm estimation)
  long preconditioner_applications = 0;  // applications of the preconditioner, not of A
  long outer_iterations = 0;             // SMALBE only
  long face_solves = 0;                  // SMALBE's face solves (qp/face.hpp), refused ones not counted
  long face_steps = 0;                   // their CG steps (not in cg_steps)
  // The work of two solves together (e.g. the QPs of one load, before and after breaks).
  Counters& operator+=(const Counters& other);
};

// The counters by name, listed once (core/fields.hpp): the adder and every writer (solution.h5's
// /solver attributes, the benchmark's JSON) walk this table; a new counter is one line here.
inline constexpr Field<Counters, long> counter_fields[] = {
    {"outer_iterations", &Counters::outer_iterations},
    {"operator_applications", &Counters::operator_applications},
    {"cg_steps", &Counters::cg_steps},
    {"expansion_steps", &Counters::expansion_steps},
    {"proportioning_steps", &Counters::proportioning_steps},
    {"preconditioner_applications", &Counters::preconditioner_applications},
    {"face_solves", &Counters::face_solves},
    {"face_steps", &Counters::face_steps},
};

inline Counters& Counters::operator+=(const Counters& other) {
  add_fields(counter_fields, *this, other);
  return *this;
}

// Residuals are of the returned x and a gradient recomputed as A x - b (+ m for SMALBE), never a
// recursively updated one. They are NaN when not computable (invalid_input, non_finite).
struct Result {
  Status status = Status::invalid_input;
  Counters counters;
  double projected_gradient_norm = 0;      // ‖gᴾ‖, absolute
  double equality_residual = 0;            // ‖Q x‖ = ‖Ĝ x‖ for orthonormal Ĝ (SMALBE), else 0
  double bound_violation = 0;              // max_i max(l_i - x_i, x_i - u_i, 0); 0 by design
  double complementarity = 0;              // max_i max(g_i⁺ (x_i - l_i), g_i⁻ (u_i - x_i)), finite bounds
  double relative_projected_gradient = 0;  // ‖gᴾ‖ / ‖b‖ (/1 if b = 0)
  double rho_final = 0;                    // SMALBE penalty ρ, 0 for MPRGP
  std::string message;                     // diagnostic when not converged
};

}  // namespace dualcell::qp
