#pragma once
// The shape every stage's main() shares: run the stage's one library call, and turn any
// exception into one line on stderr ("<stage>: error: <what>") and a non-zero exit.
#include <functional>

namespace dualcell {

// Exit codes of every stage.
inline constexpr int exit_ok = 0;
inline constexpr int exit_input_error = 1;     // bad scene, file, value or output path
inline constexpr int exit_internal_error = 3;  // a bug or an unexpected system failure

int run_stage(const char* stage, const std::function<void()>& body);

}  // namespace dualcell
