// Helpers shared by the tests: simulations from JSON text with output off and log captured.
#pragma once
#include <algorithm>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "Boundary/RigidBodySystem.h"
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
// The same for a value the code computes in Real from the scene's numbers (a parameter stored,
// a product, a square root): `doubleTol` in double, a few of float's ulps of `magnitude` in float.
constexpr double fewUlps(double doubleTol, double magnitude) { return roundoff(doubleTol, 4 * kFloatEps * magnitude); }

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

// 64 particles of radius 0.05 m (a 0.4 m cube of water) in a closed 0.6 x 1 x 0.6 m box.
inline json tinyTankScene(double stopAt) {
  json scene = json::parse(R"({
    "simulation": {"particleRadius": 0.05},
    "fluids": [{"name": "water", "blocks": [{"min": [0.1, 0.1, 0.1], "max": [0.5, 0.5, 0.5]}]}],
    "boundaries": [{"box": {"min": [0, 0, 0], "max": [0.6, 1.0, 0.6]}, "inverted": true}]
  })");
  scene["simulation"]["stopAt"] = stopAt;
  return scene;
}

// The InputError message building `scene` gives, or "(no error)".
inline std::string sceneErrorOf(const json& scene) {
  try {
    simulationFromJson(scene);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
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

// The scene's rigid bodies as their implementation (the kernel sees them as MovingBodies);
// null when every object is static.
inline RigidBodySystem* rigidBodies(Simulation& s) { return dynamic_cast<RigidBodySystem*>(s.movingBodies()); }

}  // namespace consph::test
