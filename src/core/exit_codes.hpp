#pragma once
// The exit codes of every stage, one contract (docs/reference/exit-codes.md): the tests use these names.
namespace dualcell {

inline constexpr int exit_ok = 0;
// A bad scene, file, value or output path; a failed write; an input too large for this machine
// (refused by its estimate before the work, or out of memory during it).
inline constexpr int exit_input_error = 1;
inline constexpr int exit_internal_error = 3;  // a bug or an unexpected system failure
// The computation ran but did not converge (a QP that stopped, a primal check failed, a Newton
// step of a structure that did not converge or whose energy is not finite): the output is
// written and marked as such (solution.h5 /solver status, structure.h5 /steps/converged).
inline constexpr int exit_not_converged = 4;

}  // namespace dualcell
