#pragma once
// Errors at the API boundary. An InputError is what the user did wrong (a scene key, a file, a
// value out of range); its message is one line naming where and what, and the stage prints it
// and exits non-zero. Numerical outcomes are never exceptions: they live in solver Results.
#include <stdexcept>
#include <string>

namespace dualcell {

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace dualcell
