#include "Plugins/SurfaceTension/SurfaceTension_Akinci2013.h"

#include <cmath>
#include <numbers>

#include "Simulation/ParamBinding.h"
#include "Simulation/PluginRegistry.h"
#include "Utilities/ParallelFor.h"

namespace consph {

namespace {
const PluginRegistration<NonPressureForce> registration{
    "Akinci2013", "surface tension (cohesion + curvature) and boundary adhesion (Akinci et al. 2013)",
    SurfaceTension_Akinci2013::parameters(),
    [](const Params& p, const PluginContext& c) -> std::unique_ptr<NonPressureForce> {
      return std::make_unique<SurfaceTension_Akinci2013>(p, *c.fluid);
    }};
}  // namespace

const BoundParams<SurfaceTension_Akinci2013>& SurfaceTension_Akinci2013::bound() {
  static const BoundParams<SurfaceTension_Akinci2013> table{
      bind({"surfaceTension", ParamType::Real, 0.05, "surface tension coefficient gamma (see docs/forces.md for its units)", 0,
            1e6},
           &SurfaceTension_Akinci2013::gamma_),
      bind({"boundaryAdhesion", ParamType::Real, 0.0,
            "adhesion coefficient beta towards boundaries (units as gamma's cohesion term)", 0, 1e6},
           &SurfaceTension_Akinci2013::beta_),
  };
  return table;
}

std::vector<ParamSpec> SurfaceTension_Akinci2013::parameters() { return bound().specs(); }

SurfaceTension_Akinci2013::Kernels::Kernels(Real h_)
    : h(h_),
      cohesionScale(Real(32) / (std::numbers::pi_v<Real> * std::pow(h_, Real(9)))),
      cohesionOffset(std::pow(h_, Real(6)) / 64),
      adhesionScale(Real(0.007) / std::pow(h_, Real(3.25))) {}

Real SurfaceTension_Akinci2013::Kernels::cohesion(Real r) const {
  // Eq. (2): 32 / (pi h^9) {(h - r)^3 r^3 for h/2 < r <= h; 2 (h - r)^3 r^3 - h^6 / 64 for 0 < r <= h/2}.
  if (r > h || r <= 0) return 0;
  const Real t = (h - r) * (h - r) * (h - r) * r * r * r;
  return 2 * r > h ? cohesionScale * t : cohesionScale * (2 * t - cohesionOffset);
}

Real SurfaceTension_Akinci2013::Kernels::adhesion(Real r) const {
  // Eq. (7): 0.007 / h^3.25 (-4 r^2 / h + 6 r - 2 h)^(1/4) for h/2 < r <= h.
  if (r > h || 2 * r <= h) return 0;
  return adhesionScale * std::sqrt(std::sqrt(-4 * r * r / h + 6 * r - 2 * h));
}

SurfaceTension_Akinci2013::SurfaceTension_Akinci2013(const Params& p, FluidModel& fluid)
    : normals_(fluid.fields().add<Vector3r>("normal", FieldSorted | FieldExported, Vector3r::Zero())) {
  bound().assign(p, *this);
}

void SurfaceTension_Akinci2013::addAccelerations(StepContext& ctx) {
  const FluidView& f = ctx.fluid;
  const BoundaryView& b = ctx.boundary;
  const auto& fn = ctx.fluidNeighbors;
  const auto& bn = ctx.boundaryNeighbors;
  const std::size_t n = f.size();
  const Real h = ctx.kernel.supportRadius(), rho0 = f.density0();
  const Kernels kernels(h);
  // Eq. (5): surface normals (zero inside the fluid, length ~1 at the surface).
  parallelFor(n, [&](std::size_t i) {
    Vector3r ni = Vector3r::Zero();
    const Vector3r xi = f.positions[i];
    for (Index e = fn.begin(i); e < fn.end(i); ++e) {
      const Index j = fn.indices[e];
      ni += (f.masses[j] / f.densities[j]) * fn.gradient(e, xi - f.positions[j]);
    }
    normals_[i] = h * ni;
  });
  const bool adhesion = beta_ > 0;
  parallelFor(n, [&](std::size_t i) {
    const Vector3r xi = f.positions[i], ni = normals_[i];
    const Real rhoi = f.densities[i];
    Vector3r a = Vector3r::Zero();
    for (Index e = fn.begin(i); e < fn.end(i); ++e) {
      const Index j = fn.indices[e];
      const Vector3r xij = xi - f.positions[j];
      const Real r = xij.norm();
      Vector3r aij = -gamma_ * (ni - normals_[j]);  // curvature, Eq. (4)
      if (r > 0) aij -= (gamma_ * f.masses[j] * kernels.cohesion(r) / r) * xij;  // cohesion, Eq. (1)
      a += (2 * rho0 / (rhoi + f.densities[j])) * aij;  // K_ij, Eq. (3)
    }
    if (adhesion)
      for (Index e = bn.begin(i); e < bn.end(i); ++e) {
        const Index k = bn.indices[e];
        const Vector3r xik = xi - b.positions[k];
        const Real r = xik.norm();
        if (r > 0) a -= (beta_ * b.masses[k] * kernels.adhesion(r) / r) * xik;  // Eq. (6)
      }
    f.accelerations[i] += a;
  });
}

}  // namespace consph
