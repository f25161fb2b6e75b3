// Progress display: a bar redrawn in place on a terminal, plain lines otherwise.
#pragma once
#include <cstdio>
#include <string>

#include "Utilities/Timer.h"

namespace consph {

class Progress {
 public:
  Progress(double endTime, bool enabled);
  // Called after every step; redraws at most a few times per second.
  void update(double time, std::size_t steps);
  void finish(double time, std::size_t steps);

 private:
  void draw(double time, std::size_t steps, bool final);
  double endTime_;
  bool enabled_, terminal_;
  Timer timer_;
  double lastDraw_ = -1e9;
};

}  // namespace consph
