// Progress lines through a log sink for start-up work that may run long (sampling a large mesh):
// silent for the first couple of seconds, then a line every few seconds, and a closing line
// with the total time when any was written. For the step loop's bar see Utilities/Progress.h.
#pragma once
#include <cstddef>
#include <string>

#include "Utilities/Log.h"
#include "Utilities/Timer.h"

namespace consph {

class ProgressLog {
 public:
  // `what` names the work in each line ("sampling body.obj (1000000 triangles)").
  ProgressLog(LogSink log, std::string what, std::size_t total, double quietSeconds = 2);
  // `done` of `total` items finished; writes a line when the interval has passed.
  void report(std::size_t done);
  // For work whose size is known only part of the way through.
  void setTotal(std::size_t total) { total_ = total; }
  void finish();

 private:
  LogSink log_;
  std::string what_;
  std::size_t total_;
  double quietSeconds_;
  double lastLine_ = 0;
  bool wroteAny_ = false;
  Timer timer_;
};

}  // namespace consph
