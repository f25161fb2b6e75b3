#include "Utilities/Log.h"

#include <cstdio>

namespace consph {

LogSink stderrLogSink(bool quiet) {
  return [quiet](LogLevel level, const std::string& text) {
    if (level == LogLevel::Info && quiet) return;
    std::fprintf(stderr, "%s%s\n", level == LogLevel::Warning ? "warning: " : "", text.c_str());
  };
}

}  // namespace consph
