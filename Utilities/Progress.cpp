#include "Utilities/Progress.h"

#include <unistd.h>

#include <algorithm>

namespace consph {

Progress::Progress(double endTime, bool enabled)
    : endTime_(endTime), enabled_(enabled), terminal_(isatty(fileno(stderr))) {}

void Progress::update(double time, std::size_t steps) {
  if (!enabled_) return;
  const double now = timer_.seconds();
  if (now - lastDraw_ < (terminal_ ? 0.2 : 5.0)) return;
  lastDraw_ = now;
  draw(time, steps, false);
}

void Progress::finish(double time, std::size_t steps) {
  if (enabled_) draw(time, steps, true);
}

void Progress::draw(double time, std::size_t steps, bool final) {
  const double wall = timer_.seconds();
  const double fraction = endTime_ > 0 ? std::clamp(time / endTime_, 0.0, 1.0) : 1.0;
  const double stepsPerSecond = wall > 0 ? double(steps) / wall : 0.0;
  const double eta = fraction > 0 ? wall * (1 - fraction) / fraction : 0.0;
  if (terminal_) {
    const int width = 30, filled = int(fraction * width);
    std::fprintf(stderr, "\r[%s%s] t = %.3f / %.3f s  %.1f steps/s  ETA %.0f s   ", std::string(filled, '#').c_str(),
                 std::string(width - filled, '.').c_str(), time, endTime_, stepsPerSecond, eta);
    if (final) std::fputc('\n', stderr);
  } else {
    std::fprintf(stderr, "t = %.3f / %.3f s (%3.0f%%), %zu steps, %.1f steps/s, ETA %.0f s\n", time, endTime_,
                 100 * fraction, steps, stepsPerSecond, eta);
  }
  std::fflush(stderr);
}

}  // namespace consph
