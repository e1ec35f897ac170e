#include "core/progress.hpp"

#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "core/text.hpp"

namespace dualcell {

void GeometricEta::observe(long step, double distance, double seconds) {
  if (step == 1) first_step_ = step, first_distance_ = distance, first_seconds_ = seconds;
  last_step_ = step, last_distance_ = distance, last_seconds_ = seconds;
}

std::string GeometricEta::left(double now) const {
  if (last_step_ < 3 || first_step_ != 1 || !(last_distance_ > 1) || !(first_distance_ > last_distance_)) return "";
  const double steps = static_cast<double>(last_step_ - first_step_);
  const double rate = std::pow(last_distance_ / first_distance_, 1 / steps);
  if (!(rate < 0.95)) return "";
  const double per_step = (last_seconds_ - first_seconds_) / steps;
  const double steps_left = std::log(last_distance_) / -std::log(rate);
  return ", ~" + seconds_text(std::max(0.0, steps_left * per_step - (now - last_seconds_))) + " left";
}

namespace {

// Where the in-place line must stop so that it never wraps (a wrapped line cannot be rewritten).
std::size_t terminal_columns() {
  winsize size{};
  if (::ioctl(STDERR_FILENO, TIOCGWINSZ, &size) == 0 && size.ws_col > 1) return size.ws_col - 1;
  return 79;
}

}  // namespace

Progress::Progress(std::string stage, bool enabled) : stage_(std::move(stage)), enabled_(enabled) {
  start_ = Clock::now();
  const char* term = std::getenv("TERM");
  terminal_ = ::isatty(STDERR_FILENO) == 1 && !(term && std::strcmp(term, "dumb") == 0);
  if (const char* text = std::getenv("DUALCELL_PROGRESS_INTERVAL")) {
    char* end = nullptr;
    const double v = std::strtod(text, &end);
    if (end != text && *end == '\0' && std::isfinite(v) && v >= 0)
      interval_ = std::min(v, 1e6);
    else if (enabled_)
      std::fprintf(stderr,
                   "%s: warning: DUALCELL_PROGRESS_INTERVAL = '%s' is not a number of seconds >= 0: %g s used\n",
                   stage_.c_str(), clipped(text).c_str(), interval_);
  }
  // A terminal shows the state from the start; a log gets its first line after one interval.
  next_ = terminal_ ? start_
                    : start_ + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(interval_));
}

std::string seconds_text(double seconds) {
  char text[48];
  if (!std::isfinite(seconds) || seconds < 0) return "?";
  if (seconds < 60)
    std::snprintf(text, sizeof text, "%.1f s", seconds);
  else if (seconds < 3600)
    std::snprintf(text, sizeof text, "%d min %02d s", static_cast<int>(seconds / 60), static_cast<int>(seconds) % 60);
  else
    std::snprintf(text, sizeof text, "%d h %02d min", static_cast<int>(seconds / 3600),
                  static_cast<int>(seconds / 60) % 60);
  return text;
}

double Progress::seconds() const { return seconds_since(start_); }

bool Progress::due() {
  const Clock::time_point now = Clock::now();
  if (now < next_) return false;
  const double wait = terminal_ ? 0.2 : interval_;
  next_ = now + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(wait));
  return true;
}

void Progress::show(const std::string& text) {
  std::string line = stage_ + ": " + text;
  if (terminal_) {
    const std::size_t columns = terminal_columns();
    if (line.size() > columns) {  // cut at a character boundary (UTF-8), never inside one
      std::size_t cut = columns;
      while (cut > 0 && (static_cast<unsigned char>(line[cut]) & 0xC0) == 0x80) --cut;
      line.resize(cut);
    }
    // Return, the line, then erase what an earlier, longer line left to its right.
    std::fprintf(stderr, "\r%s\x1b[K", line.c_str());
    line_shown_ = true;
  } else {
    std::fprintf(stderr, "%s\n", line.c_str());
  }
  std::fflush(stderr);
}

void Progress::message(const std::string& line) {
  if (!enabled_) return;
  if (terminal_ && line_shown_) std::fprintf(stderr, "\r\x1b[K");
  line_shown_ = false;
  std::fprintf(stderr, "%s: %s\n", stage_.c_str(), line.c_str());
  std::fflush(stderr);
  if (terminal_) next_ = Clock::now();  // redraw the state at the next update
}

void Progress::finish() {
  if (!enabled_ || !terminal_ || !line_shown_) return;
  std::fprintf(stderr, "\r\x1b[K");
  std::fflush(stderr);
  line_shown_ = false;
}

}  // namespace dualcell
