// Helpers shared by the tests: simulations from JSON text with output off and log captured.
#pragma once
#include <sys/wait.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "Simulation/Simulation.h"

namespace consph::test {

// Round-off of the build's Real (CONSPH_DOUBLE=ON: double, OFF: float). Tolerances that cover
// round-off, not physics, are written with these: CI builds double, whose tolerances were tuned
// for it and stay as they are; a float build gets a tolerance derived from float's epsilon
// (2^-23 = 1.19e-7) with a comment saying which round-off it covers.
inline constexpr bool kDoubleBuild = sizeof(Real) == sizeof(double);
inline constexpr double kFloatEps = std::numeric_limits<float>::epsilon();

// The tolerance of this build: `doubleTol` in a double build (unchanged from before tests were
// made precision-aware), `floatTol` in a float build.
constexpr double roundoff(double doubleTol, double floatTol) { return kDoubleBuild ? doubleTol : floatTol; }

struct CapturedLog {
  std::vector<std::string> warnings, infos;
  LogSink sink() {
    return [this](LogLevel level, const std::string& text) {
      if (level == LogLevel::Warning) warnings.push_back(text);
      if (level == LogLevel::Info) infos.push_back(text);
    };
  }
};

inline std::unique_ptr<Simulation> simulationFromJson(json scene, const LogSink& log = {}) {
  scene["output"] = {{"enabled", false}};
  return std::make_unique<Simulation>(parseScene(scene, CONSPH_TEST_DATA_DIR "/scenes", log), builtinPlugins(),
                                      log ? log : LogSink([](LogLevel, const std::string&) {}));
}

inline std::string dataPath(const std::string& relative) { return std::string(CONSPH_TEST_DATA_DIR) + "/" + relative; }

// The largest particle density, kg/m^3.
inline Real maxDensity(const FluidModel& f) { return *std::max_element(f.densities.begin(), f.densities.end()); }

// Least-squares line y = slope x + intercept through the points added (pressure against height
// or depth in the hydrostatic and buoyancy tests).
struct LineFit {
  double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
  void add(double x, double y) {
    n += 1, sx += x, sy += y, sxx += x * x, sxy += x * y;
  }
  double slope() const { return (n * sxy - sx * sy) / (n * sxx - sx * sx); }
  double intercept() const { return (sy - slope() * sx) / n; }
};

// The free surface height: the mean height of the `layerCount` highest particles (the top
// layer) plus half a particle spacing. A mean over the layer is robust to one particle riding
// on top of the others.
inline Real surfaceHeight(const FluidModel& f, std::size_t layerCount, Real halfSpacing) {
  std::vector<Real> heights(f.size());
  for (std::size_t i = 0; i < f.size(); ++i) heights[i] = f.positions[i][1];
  layerCount = std::min(layerCount, heights.size());
  std::partial_sort(heights.begin(), heights.begin() + layerCount, heights.end(), std::greater<Real>());
  Real sum = 0;
  for (std::size_t i = 0; i < layerCount; ++i) sum += heights[i];
  return sum / Real(layerCount) + halfSpacing;
}

// Runs a shell command; its exit status and its stdout and stderr together (CLI tests).
struct CommandResult {
  int status;
  std::string output;
};
inline CommandResult runCommand(const std::string& command) {
  CommandResult r{0, ""};
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  char buffer[4096];
  while (std::fgets(buffer, sizeof(buffer), pipe)) r.output += buffer;
  const int status = pclose(pipe);
  r.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

// An empty folder of this name under the system's temporary folder.
inline std::string tempDir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir.string();
}

}  // namespace consph::test
