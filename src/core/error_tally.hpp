#pragma once
// The one tally of a check's relative errors: how many points (or paths) it counted, the largest
// error and the root mean square. Every check of a law against data it was not built from (the
// compact laws against the exact law, the exact law against the sweep's solves, a fit against
// held-out directions) keeps its numbers in one.
#include <cmath>
#include <limits>

namespace dualcell {

struct ErrorTally {
  int count = 0;
  double max = 0;
  double sum_of_squares = 0;

  // Counts one error; a non-finite one (the law gave no answer) counts as the worst, +inf. True
  // when it is the largest so far (the first always is): where a check records its worst point.
  bool add(double error) {
    if (!std::isfinite(error)) error = std::numeric_limits<double>::infinity();
    ++count;
    sum_of_squares += error * error;
    const bool largest = count == 1 || error > max;
    if (largest) max = error;
    return largest;
  }
  // NaN while nothing is counted.
  double max_error() const { return count > 0 ? max : std::numeric_limits<double>::quiet_NaN(); }
  double rms_error() const {
    return count > 0 ? std::sqrt(sum_of_squares / count) : std::numeric_limits<double>::quiet_NaN();
  }
};

}  // namespace dualcell
