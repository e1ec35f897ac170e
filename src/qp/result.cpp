#include "qp/result.hpp"

namespace dualcell::qp {

const char* to_string(Status status) {
  switch (status) {
    case Status::converged:
      return "converged";
    case Status::max_iterations:
      return "max_iterations";
    case Status::stagnated:
      return "stagnated";
    case Status::invalid_input:
      return "invalid_input";
    case Status::non_finite:
      return "non_finite";
    case Status::unbounded:
      return "unbounded";
  }
  return "unknown";
}

}  // namespace dualcell::qp
