#include "Plugins/Viscosity/Viscosity_Standard.h"

#include "Simulation/PluginRegistry.h"

namespace consph {

namespace {
const PluginRegistration<NonPressureForce> registration{
    "StandardViscosity", "SPH-Laplacian viscosity (Morris 1997 / Monaghan 2005), kinematic viscosity in m^2/s",
    Viscosity_Standard::parameters(), [](const Params& p, const PluginContext&) -> std::unique_ptr<NonPressureForce> {
      return std::make_unique<Viscosity_Standard>(p);
    }};
}  // namespace

std::vector<ParamSpec> Viscosity_Standard::parameters() {
  return {{"viscosity", ParamType::Real, 0.01, "kinematic viscosity nu of the fluid, m^2/s", 0, 1e6},
          {"boundaryViscosity", ParamType::Real, 0.0, "kinematic viscosity towards boundaries, m^2/s", 0, 1e6}};
}

Viscosity_Standard::Viscosity_Standard(const Params& p)
    : viscosity_(p.real("viscosity")), boundaryViscosity_(p.real("boundaryViscosity")) {}

void Viscosity_Standard::addAccelerations(StepContext& ctx) {
  FluidModel& f = ctx.fluid;
  const BoundarySamples& b = ctx.boundary;
  const auto& fn = ctx.fluidNeighbors;
  const auto& bn = ctx.boundaryNeighbors;
  const Real h = ctx.kernel.supportRadius(), eps = Real(0.01) * h * h, d = 10;  // 2 (dim + 2)
  const Real rho0 = f.density0();
  const bool boundary = boundaryViscosity_ > 0;
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t i = 0; i < std::ptrdiff_t(f.size()); ++i) {
    const Vector3r xi = f.positions[i], vi = f.velocities[i];
    Vector3r a = Vector3r::Zero();
    for (Index e = fn.begin(i); e < fn.end(i); ++e) {
      const Index j = fn.indices[e];
      const Vector3r xij = xi - f.positions[j];
      a += (f.masses[j] / f.densities[j]) * (vi - f.velocities[j]).dot(xij) / (xij.squaredNorm() + eps) * fn.gradW[e];
    }
    a *= d * viscosity_;
    if (boundary) {
      Vector3r ab = Vector3r::Zero();
      for (Index e = bn.begin(i); e < bn.end(i); ++e) {
        const Index k = bn.indices[e];
        const Vector3r xik = xi - b.positions[k];
        ab += (b.masses[k] / rho0) * (vi - b.velocities[k]).dot(xik) / (xik.squaredNorm() + eps) * bn.gradW[e];
      }
      a += d * boundaryViscosity_ * ab;
    }
    f.accelerations[i] += a;
  }
}

}  // namespace consph
