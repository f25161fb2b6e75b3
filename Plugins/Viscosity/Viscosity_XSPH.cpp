#include "Plugins/Viscosity/Viscosity_XSPH.h"

#include "Simulation/ParamBinding.h"
#include "Simulation/PluginRegistry.h"
#include "Utilities/ParallelFor.h"

namespace consph {

namespace {
const PluginRegistration<NonPressureForce> registration{
    "XSPH", "XSPH velocity smoothing (Monaghan 1989) as an acceleration; dimensionless factor, not a kinematic viscosity",
    Viscosity_XSPH::parameters(), [](const Params& p, const PluginContext&) -> std::unique_ptr<NonPressureForce> {
      return std::make_unique<Viscosity_XSPH>(p);
    }};
}  // namespace

const BoundParams<Viscosity_XSPH>& Viscosity_XSPH::bound() {
  static const BoundParams<Viscosity_XSPH> table{
      bind({"viscosity", ParamType::Real, 0.01, "XSPH factor eps, dimensionless (fraction smoothed per step)", 0, 1},
           &Viscosity_XSPH::factor_),
      bind({"boundaryViscosity", ParamType::Real, 0.0, "XSPH factor towards boundaries, dimensionless", 0, 1},
           &Viscosity_XSPH::boundaryFactor_),
  };
  return table;
}

std::vector<ParamSpec> Viscosity_XSPH::parameters() { return bound().specs(); }

Viscosity_XSPH::Viscosity_XSPH(const Params& p) { bound().assign(p, *this); }

void Viscosity_XSPH::addAccelerations(StepContext& ctx) {
  const FluidView& f = ctx.fluid;
  const BoundaryView& b = ctx.boundary;
  const auto& fn = ctx.fluidNeighbors;
  const auto& bn = ctx.boundaryNeighbors;
  // dt is the previous step's (forces run before the CFL step): the smoothing per step is eps.
  const Real invDt = Real(1) / ctx.dt;
  const bool boundary = boundaryFactor_ > 0;
  parallelFor(f.size(), [&](std::size_t i) {
    const Vector3r xi = f.positions[i], vi = f.velocities[i];
    const Real rhoi = f.densities[i];
    Vector3r s = Vector3r::Zero();
    for (Index e = fn.begin(i); e < fn.end(i); ++e) {
      const Index j = fn.indices[e];
      s += (2 * f.masses[j] / (rhoi + f.densities[j]) * ctx.kernel.W(xi - f.positions[j])) * (vi - f.velocities[j]);
    }
    Vector3r a = -factor_ * invDt * s;
    if (boundary) {
      Vector3r sb = Vector3r::Zero();
      for (Index e = bn.begin(i); e < bn.end(i); ++e) {
        const Index k = bn.indices[e];
        sb += (b.masses[k] / rhoi * ctx.kernel.W(xi - b.positions[k])) * (vi - b.velocities[k]);
      }
      a -= boundaryFactor_ * invDt * sb;
    }
    f.accelerations[i] += a;
  });
}

}  // namespace consph
