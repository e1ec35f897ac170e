#pragma once
// Progress of a long computation on stderr, for the user watching it (never for a file or a
// test to parse). On a terminal: one line "<stage>: <text>", rewritten in place at most every
// 0.2 s and erased by finish(), so that what follows starts on a clean line. Otherwise (a pipe,
// a log file): a plain line, the first after `interval` seconds and then at most one per
// interval (default 5 s; DUALCELL_PROGRESS_INTERVAL=<seconds> sets it), so that short runs log
// nothing. A disabled Progress (--quiet, MPI ranks other than 0) prints nothing.
//
// update() takes the text as a callable and runs it only when a line is due: a caller in a hot
// loop pays one clock read per call, and the computation never waits for output.
#include <chrono>
#include <string>

namespace dualcell {

// The seconds of the steady clock since t: every measured duration (timings, progress).
inline double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// "12.3 s", "4 min 05 s", "2 h 03 min": a duration as a person reads it.
std::string seconds_text(double seconds);

// The time left of an iteration whose distance to convergence (a residual over its tolerance, > 1
// until it converges) falls about geometrically per step, from the rate seen since step 1: the
// estimate of the QP's progress line.
class GeometricEta {
 public:
  void observe(long step, double distance, double seconds);
  // ", ~<time> left" at `now`, or "" while it cannot tell (before step 3, not falling, or falling
  // by less than 5 % a step, where the estimate would swing).
  std::string left(double now) const;

 private:
  long first_step_ = 0, last_step_ = 0;
  double first_distance_ = 0, last_distance_ = 0, first_seconds_ = 0, last_seconds_ = 0;
};

class Progress {
 public:
  Progress(std::string stage, bool enabled);
  ~Progress() { finish(); }
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  bool enabled() const { return enabled_; }
  double seconds() const;  // since construction

  template <typename Text>
  void update(Text&& text) {
    if (enabled_ && due()) show(text());
  }
  // A line that stays (a finished load step): printed at once, above the in-place line.
  void message(const std::string& line);
  // Erases the in-place line (on a terminal); nothing otherwise. Called by the destructor.
  void finish();

 private:
  using Clock = std::chrono::steady_clock;
  bool due();
  void show(const std::string& text);

  std::string stage_;
  bool enabled_ = false, terminal_ = false, line_shown_ = false;
  double interval_ = 5.0;  // seconds between lines
  Clock::time_point start_, next_;
};

}  // namespace dualcell
