#include "Plugins/Viscosity/Viscosity_Standard.h"

#include "Plugins/Viscosity/ViscosityLaplacian.h"
#include "Simulation/PluginRegistry.h"

namespace consph {

namespace {
const PluginRegistration<NonPressureForce> registration{
    "StandardViscosity", "explicit SPH-Laplacian viscosity (Morris et al. 1997), kinematic viscosity in m^2/s",
    Viscosity_Standard::parameters(), [](const Params& p, const PluginContext&) -> std::unique_ptr<NonPressureForce> {
      return std::make_unique<Viscosity_Standard>(p);
    }};
}  // namespace

std::vector<ParamSpec> Viscosity_Standard::parameters() {
  return {{"viscosity", ParamType::Real, 0.01, "kinematic viscosity nu of the fluid, m^2/s", 0, 1e6},
          {"boundaryViscosity", ParamType::Real, 0.0, "kinematic viscosity towards boundaries, m^2/s (0: free slip)", 0, 1e6}};
}

Viscosity_Standard::Viscosity_Standard(const Params& p)
    : viscosity_(p.real("viscosity")), boundaryViscosity_(p.real("boundaryViscosity")) {}

void Viscosity_Standard::addAccelerations(StepContext& ctx) {
  using namespace viscosity;
  FluidModel& f = ctx.fluid;
  const Real eps = regularisation(ctx.kernel), rho0 = f.density0();
  const bool boundary = boundaryViscosity_ > 0;
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t i = 0; i < std::ptrdiff_t(f.size()); ++i) {
    const Real rhoi = f.densities[i];
    // ViscosityLaplacian.h: fluid and boundary terms.
    Vector3r a = (kLaplacianFactor * viscosity_ * rho0 / rhoi) * fluidSum(f, ctx.fluidNeighbors, i, f.velocities.data(), eps);
    if (boundary)
      a += (kLaplacianFactor * boundaryViscosity_ / rhoi) *
           boundarySum(ctx.boundary, ctx.boundaryNeighbors, i, f.positions[i], f.velocities[i], eps, true);
    f.accelerations[i] += a;
  }
}

}  // namespace consph
