#include "Plugins/Vorticity/MicropolarModel_Bender2019.h"

#include <Eigen/Geometry>  // cross

#include "Simulation/ParamBinding.h"
#include "Simulation/PluginRegistry.h"
#include "Utilities/ParallelFor.h"

namespace consph {

namespace {
const PluginRegistration<NonPressureForce> registration{
    "Micropolar", "micropolar vorticity: angular velocity field coupled to the velocity (Bender et al. 2019)",
    MicropolarModel_Bender2019::parameters(),
    [](const Params& p, const PluginContext& c) -> std::unique_ptr<NonPressureForce> {
      return std::make_unique<MicropolarModel_Bender2019>(p, *c.fluid);
    }};
}  // namespace

const BoundParams<MicropolarModel_Bender2019>& MicropolarModel_Bender2019::bound() {
  static const BoundParams<MicropolarModel_Bender2019> table{
      bind({"vorticity", ParamType::Real, 0.01, "transfer coefficient nu_t between velocity and angular velocity, m^2/s", 0, 1e3},
           &MicropolarModel_Bender2019::vorticity_),
      bind({"inertiaInverse", ParamType::Real, 0.5, "inverse micro-inertia Theta^-1, 1/m^2", 0, 1e6},
           &MicropolarModel_Bender2019::inertiaInverse_),
      bind({"viscosityOmega", ParamType::Real, 0.1,
            "angular viscosity zeta, m^2 (Theta^-1 zeta: dimensionless XSPH factor on omega)", 0, 1e3},
           &MicropolarModel_Bender2019::viscosityOmega_),
  };
  return table;
}

std::vector<ParamSpec> MicropolarModel_Bender2019::parameters() { return bound().specs(); }

MicropolarModel_Bender2019::MicropolarModel_Bender2019(const Params& p, FluidModel& fluid)
    : omega_(fluid.fields().add<Vector3r>("angularVelocity", FieldSorted | FieldExported, Vector3r::Zero())) {
  bound().assign(p, *this);
}

void MicropolarModel_Bender2019::addAccelerations(StepContext& ctx) {
  const FluidView& f = ctx.fluid;
  const BoundaryView& b = ctx.boundary;
  const auto& fn = ctx.fluidNeighbors;
  const auto& bn = ctx.boundaryNeighbors;
  const std::size_t n = f.size();
  const Real dt = ctx.dt, nuT = vorticity_, thetaInv = inertiaInverse_;
  const Real smoothing = thetaInv * viscosityOmega_ / dt;
  angularAcceleration_.resize(f.size());
  // As a lambda body this loop compiles (GCC 12, float, -march=native) with some of its
  // a b - c d terms (cross products, the last line) fused the other way round than as a raw
  // OpenMP loop, fma(-c, d, a b) instead of fma(a, b, -c d): float results moved in the last bits
  // when it went behind the dispatch (double ones stayed the same; measured 2026-12-02).
  parallelFor(n, [&](std::size_t i) {
    const Vector3r xi = f.positions[i], vi = f.velocities[i], wi = omega_[i];
    Vector3r curlOmega = Vector3r::Zero(), curlV = Vector3r::Zero(), smooth = Vector3r::Zero();
    for (Index e = fn.begin(i); e < fn.end(i); ++e) {
      const Index j = fn.indices[e];
      const Real mj = f.masses[j];
      const Vector3r wij = wi - omega_[j], gradW = fn.gradient(e, xi - f.positions[j]);
      curlOmega += mj * wij.cross(gradW);
      curlV += mj * (vi - f.velocities[j]).cross(gradW);
      smooth += (mj / f.densities[j] * ctx.kernel.W(xi - f.positions[j])) * wij;
    }
    for (Index e = bn.begin(i); e < bn.end(i); ++e) {
      const Index k = bn.indices[e];
      curlOmega += b.masses[k] * wi.cross(bn.gradW[e]);  // omega_k = 0
      curlV += b.masses[k] * (vi - b.velocities[k]).cross(bn.gradW[e]);
    }
    const Real invRho = Real(1) / f.densities[i];
    f.accelerations[i] += nuT * invRho * curlOmega;
    angularAcceleration_[i] = thetaInv * nuT * (invRho * curlV - 2 * wi) - smoothing * smooth;
  });
  // Explicit Euler on omega, after every particle has read the old omega_j.
  parallelFor(n, [&](std::size_t i) { omega_[i] += dt * angularAcceleration_[i]; });
}

}  // namespace consph
