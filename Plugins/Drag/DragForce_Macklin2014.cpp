#include "Plugins/Drag/DragForce_Macklin2014.h"

#include "Simulation/ParamBinding.h"
#include "Simulation/PluginRegistry.h"
#include "Utilities/ParallelFor.h"

namespace consph {

namespace {
const PluginRegistration<NonPressureForce> registration{
    "Macklin2014", "surface drag proportional to the missing density (Macklin et al. 2014)",
    DragForce_Macklin2014::parameters(), [](const Params& p, const PluginContext&) -> std::unique_ptr<NonPressureForce> {
      return std::make_unique<DragForce_Macklin2014>(p);
    }};
}  // namespace

const BoundParams<DragForce_Macklin2014>& DragForce_Macklin2014::bound() {
  static const BoundParams<DragForce_Macklin2014> table{
      bind({"drag", ParamType::Real, 0.01, "drag coefficient c, kg/s (force per m/s of relative velocity)", 0, 1e6},
           &DragForce_Macklin2014::drag_),
      bind({"airVelocity", ParamType::Vector3, json::array({0, 0, 0}), "velocity of the surrounding air, m/s", -1e6, 1e6},
           &DragForce_Macklin2014::airVelocity_),
  };
  return table;
}

std::vector<ParamSpec> DragForce_Macklin2014::parameters() { return bound().specs(); }

DragForce_Macklin2014::DragForce_Macklin2014(const Params& p) { bound().assign(p, *this); }

void DragForce_Macklin2014::addAccelerations(StepContext& ctx) {
  const FluidView& f = ctx.fluid;
  const Real invRho0 = Real(1) / f.density0();
  parallelFor(f.size(), [&](std::size_t i) {
    const Real missing = std::max(1 - f.densities[i] * invRho0, Real(0));
    f.accelerations[i] -= (drag_ / f.masses[i] * missing) * (f.velocities[i] - airVelocity_);
  });
}

}  // namespace consph
