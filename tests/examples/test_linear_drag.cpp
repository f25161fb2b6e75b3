// docs/extending.md's worked example, built and run: the LinearDrag force (docs/examples/) is
// registered by its own .cpp, a scene names it, and a block moving through still air slows as
// exp(-k t) while the same block without it keeps its speed.
#include <gtest/gtest.h>

#include <cmath>

#include "TestUtil.h"

using namespace consph;

namespace {

// The mean velocity of a free 0.2 m block (no gravity, no walls) launched at 1 m/s along x,
// after `time` s, with the forces `forces`.
Vector3r meanVelocityAfter(double time, const json& forces) {
  json scene = {{"simulation", {{"particleRadius", 0.02}, {"gravity", {0, 0, 0}}, {"stopAt", time}}},
                {"fluids", {{{"forces", forces}, {"blocks", {{{"min", {0, 0, 0}}, {"max", {0.2, 0.2, 0.2}}, {"velocity", {1, 0, 0}}}}}}}}};
  auto sim = test::simulationFromJson(scene);
  sim->run(Real(time));
  Vector3r mean = Vector3r::Zero();
  for (const Vector3r& v : sim->fluid().velocities) mean += v;
  return mean / Real(sim->fluid().size());
}

}  // namespace

TEST(ExtendingExample, LinearDragIsRegisteredWithItsParameters) {
  const auto* entry = builtinPlugins().forces.find("LinearDrag");
  ASSERT_NE(entry, nullptr);
  ASSERT_EQ(entry->params.size(), 2u);
  EXPECT_EQ(entry->params[0].name, "coefficient");
  // Out of its declared range: refused with the JSON path.
  json scene = test::tinyTankScene(0.01);
  scene["fluids"][0]["forces"] = {{{"type", "LinearDrag"}, {"coefficient", -1}}};
  EXPECT_NE(test::sceneErrorOf(scene).find("fluids[0].forces[0].coefficient"), std::string::npos) << test::sceneErrorOf(scene);
}

TEST(ExtendingExample, LinearDragSlowsABlockAsExpMinusKt) {
  const double k = 2, t = 0.1;
  const Vector3r dragged = meanVelocityAfter(t, {{{"type", "LinearDrag"}, {"coefficient", k}}});
  // Explicit Euler multiplies by (1 - k dt) per step: exp(-k t) to O(k^2 t dt) = 1e-3 here.
  EXPECT_NEAR(double(dragged[0]), std::exp(-k * t), 0.01 * std::exp(-k * t));
  EXPECT_NEAR(double(dragged[1]), 0, 1e-9);
  // Without it, pressure forces are internal: the block's momentum stays.
  const Vector3r free = meanVelocityAfter(t, json::array());
  EXPECT_NEAR(double(free[0]), 1, 1e-9);
}
