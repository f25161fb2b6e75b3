// Wall-clock timing of the step's phases.
#pragma once
#include <chrono>

namespace consph {

class Timer {
 public:
  Timer() : start_(Clock::now()) {}
  double seconds() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }

 private:
  using Clock = std::chrono::steady_clock;
  Clock::time_point start_;
};

// Adds the lifetime of the scope to an accumulator.
class ScopedTimer {
 public:
  explicit ScopedTimer(double& accumulator) : accumulator_(accumulator) {}
  ~ScopedTimer() { accumulator_ += timer_.seconds(); }

 private:
  double& accumulator_;
  Timer timer_;
};

}  // namespace consph
