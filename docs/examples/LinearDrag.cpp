#include "docs/examples/LinearDrag.h"

#include "Simulation/PluginRegistry.h"
#include "Utilities/ParallelFor.h"

namespace consph {

namespace {
// Adds "LinearDrag" to the built-in catalogue before main() runs: the scene's
// {"type": "LinearDrag", ...} finds it by this name (case-insensitive).
const PluginRegistration<NonPressureForce> registration{
    "LinearDrag", "linear (Stokes) drag towards the air's velocity, a = -k (v - v_air) (docs/extending.md's example)",
    LinearDrag::parameters(), [](const Params& p, const PluginContext&) -> std::unique_ptr<NonPressureForce> {
      return std::make_unique<LinearDrag>(p);
    }};
}  // namespace

std::vector<ParamSpec> LinearDrag::parameters() {
  return {{"coefficient", ParamType::Real, 1.0, "drag rate k, 1/s (a velocity relaxes as exp(-k t))", 0, 1e6},
          {"airVelocity", ParamType::Vector3, json::array({0, 0, 0}), "velocity of the surrounding air, m/s", -1e6, 1e6}};
}

// Read once, here: the scene's values were checked against parameters() before this runs.
LinearDrag::LinearDrag(const Params& p) : coefficient_(p.real("coefficient")), airVelocity_(p.vector3("airVelocity")) {}

void LinearDrag::addAccelerations(StepContext& ctx) {
  const FluidView& f = ctx.fluid;
  // One particle at a time, no neighbours: a plain parallel loop, each i written by one thread.
  parallelFor(f.size(), [&](std::size_t i) { f.accelerations[i] -= coefficient_ * (f.velocities[i] - airVelocity_); });
}

}  // namespace consph
