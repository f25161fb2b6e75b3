#include "Plugins/Viscosity/Viscosity_Standard.h"

#include <algorithm>
#include <limits>

#include "Plugins/Viscosity/ViscosityLaplacian.h"
#include "Simulation/ParamBinding.h"
#include "Simulation/PluginRegistry.h"
#include "Utilities/ParallelFor.h"

namespace consph {

namespace {
const PluginRegistration<NonPressureForce> registration{
    "StandardViscosity", "explicit SPH-Laplacian viscosity (Morris et al. 1997), kinematic viscosity in m^2/s",
    Viscosity_Standard::parameters(), [](const Params& p, const PluginContext&) -> std::unique_ptr<NonPressureForce> {
      return std::make_unique<Viscosity_Standard>(p);
    }};
}  // namespace

const BoundParams<Viscosity_Standard>& Viscosity_Standard::bound() {
  static const BoundParams<Viscosity_Standard> table{
      bind({"viscosity", ParamType::Real, 0.01, "kinematic viscosity nu of the fluid, m^2/s", 0, 1e6},
           &Viscosity_Standard::viscosity_),
      bind({"boundaryViscosity", ParamType::Real, 0.0, "kinematic viscosity towards boundaries, m^2/s (0: free slip)", 0, 1e6},
           &Viscosity_Standard::boundaryViscosity_),
  };
  return table;
}

std::vector<ParamSpec> Viscosity_Standard::parameters() { return bound().specs(); }

Viscosity_Standard::Viscosity_Standard(const Params& p) { bound().assign(p, *this); }

Real Viscosity_Standard::maxStableTimeStep(const CubicSplineKernel& kernel) const {
  // Morris, Fox, Zhu 1997, Section 2.3: dt <= 0.125 h^2 / nu for the explicit viscous term, h
  // the smoothing length (their kernel's support is a multiple of h; the cubic spline's is 2h).
  // The boundary term is explicit as well: the larger of the two viscosities sets it.
  const Real nu = std::max(viscosity_, boundaryViscosity_);
  if (nu <= 0) return std::numeric_limits<Real>::infinity();
  const Real h = kernel.supportRadius() / 2;
  return Real(0.125) * h * h / nu;
}

void Viscosity_Standard::addAccelerations(StepContext& ctx) {
  using namespace viscosity;
  const FluidView& f = ctx.fluid;
  const Real eps = regularisation(ctx.kernel), rho0 = f.density0();
  const bool boundary = boundaryViscosity_ > 0;
  parallelFor(f.size(), [&](std::size_t i) {
    const Real rhoi = f.densities[i];
    // ViscosityLaplacian.h: fluid and boundary terms.
    Vector3r a = (kLaplacianFactor * viscosity_ * rho0 / rhoi) * fluidSum(f, ctx.fluidNeighbors, i, f.velocities.data(), eps);
    if (boundary)
      a += (kLaplacianFactor * boundaryViscosity_ / rhoi) *
           boundarySum(ctx.boundary, ctx.boundaryNeighbors, i, f.positions[i], f.velocities[i], eps, true);
    f.accelerations[i] += a;
  });
}

}  // namespace consph
