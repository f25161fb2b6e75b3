#include "Utilities/ProgressLog.h"

#include <cstdio>
#include <utility>

namespace consph {

ProgressLog::ProgressLog(LogSink log, std::string what, std::size_t total, double quietSeconds)
    : log_(std::move(log)), what_(std::move(what)), total_(total), quietSeconds_(quietSeconds) {}

void ProgressLog::report(std::size_t done) {
  if (!log_) return;
  const double now = timer_.seconds();
  if (now < quietSeconds_ || now - lastLine_ < quietSeconds_) return;
  lastLine_ = now;
  wroteAny_ = true;
  char line[64];
  std::snprintf(line, sizeof(line), ": %.0f %% after %.1f s", total_ > 0 ? 100.0 * double(done) / double(total_) : 100.0, now);
  log_(LogLevel::Info, what_ + line);
}

void ProgressLog::finish() {
  if (!log_ || !wroteAny_) return;
  char line[48];
  std::snprintf(line, sizeof(line), ": done in %.1f s", timer_.seconds());
  log_(LogLevel::Info, what_ + line);
}

}  // namespace consph
