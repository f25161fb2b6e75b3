#include "Utilities/ThreadCount.h"

#include <algorithm>
#include <thread>

namespace consph {

int maxThreadCount() {
  const int hardware = std::max(1, int(std::thread::hardware_concurrency()));
  return std::min(1024, 4 * hardware);
}

int clampThreadCount(long long requested, std::string& warning) {
  const int limit = maxThreadCount();
  if (requested <= limit) return int(requested);
  warning = std::to_string(requested) + " threads clamped to " + std::to_string(limit) + " (4x the " +
            std::to_string(std::max(1u, std::thread::hardware_concurrency())) + " hardware threads, at most 1024)";
  return limit;
}

}  // namespace consph
