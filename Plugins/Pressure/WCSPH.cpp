#include "Plugins/Pressure/WCSPH.h"

#include <cmath>

#include "Plugins/Pressure/SphPressureTerms.h"
#include "Simulation/ParamBinding.h"
#include "Simulation/PluginRegistry.h"
#include "Utilities/ParallelFor.h"

namespace consph {

namespace {
const PluginRegistration<PressureSolver> registration{
    "WCSPH", "Weakly compressible SPH with the Tait equation (Becker & Teschner 2007); needs small time steps",
    WCSPH::parameters(), [](const Params& p, const PluginContext& c) -> std::unique_ptr<PressureSolver> {
      return std::make_unique<WCSPH>(p, c.boundaryPressure);
    }};
}  // namespace

const BoundParams<WCSPH::Settings>& WCSPH::bound() {
  static const BoundParams<Settings> table{
      bind({"stiffness", ParamType::Real, 50000.0, "Tait stiffness k, Pa", 1e-6, 1e12}, &Settings::stiffness),
      bind({"exponent", ParamType::Real, 7.0, "Tait exponent gamma", 1, 20}, &Settings::exponent),
  };
  return table;
}

std::vector<ParamSpec> WCSPH::parameters() { return bound().specs(); }

WCSPH::WCSPH(const Params& p, BoundaryPressure treatment) : treatment_(treatment) { bound().assign(p, settings_); }

void WCSPH::solve(StepContext& ctx) {
  stats_ = PressureSolverStats();
  const FluidView& f = ctx.fluid;
  const Real rho0 = f.density0(), dt = ctx.dt;
  const std::size_t n = f.size();
  beta_.resize(f.size());
  const double errorSum = parallelSum<double>(n, [&](std::size_t i) {
    const Real ratio = f.densities[i] / rho0;
    f.pressures[i] = std::max(Real(0), settings_.stiffness * (std::pow(ratio, settings_.exponent) - Real(1)));
    beta_[i] = f.pressures[i] / (f.densities[i] * f.densities[i]);
    return std::max(ratio - Real(1), Real(0));
  });
  // Boundary pressures (extrapolation fits them to the fresh p_j).
  treatment_.beginStep(ctx);
  if (treatment_.extrapolates()) treatment_.extrapolate([&](Index j) { return f.pressures[j]; });
  const std::vector<Real>& pk = treatment_.boundaryPressures();
  parallelFor(ctx.fluidNeighbors.work, n, [&](std::size_t i) {
    // Eq. (9), boundary: Eq. (33) (consistent) or Eq. (16) (mirroring, extrapolation).
    const Vector3r a = fluidPressureAcceleration(ctx, i, beta_) + treatment_.acceleration(ctx, i, beta_[i], f.pressures[i], pk);
    f.velocities[i] += dt * a;
  });
  stats_.densityError = n ? Real(errorSum / double(n)) : Real(0);
}

Real WCSPH::maxStableTimeStep(Real particleRadius, Real density0) const {
  // An explicit weakly compressible solve is stable only while a pressure wave crosses less than
  // a particle per step: the CFL condition on the speed of sound, dt <= 0.4 (2r) / c_s (Becker &
  // Teschner 2007, Sec. 5; Monaghan 1994), with the Tait equation's c_s^2 = dp/drho at rho0 =
  // gamma k / rho0 (18.7 m/s at the defaults). Without it the default cap (the flow's CFL, 5 ms)
  // let a resting tank, a dam break and a floating box blow up at r = 0.025-0.005 (measured
  // 2026-12-02: 4.3 ms steps against a 1.07 ms bound); at 1 ms the tank rested for 2 s.
  const Real soundSpeed = std::sqrt(settings_.exponent * settings_.stiffness / density0);
  return Real(0.4) * 2 * particleRadius / soundSpeed;
}

void WCSPH::boundaryImpulses(const StepContext& ctx, std::vector<Vector3r>& impulsePerPair) const {
  // The reaction of the explicit boundary term, Eq. (35).
  treatment_.reactionImpulses(ctx, ctx.dt, beta_, ctx.fluid.pressures, impulsePerPair);
}

}  // namespace consph
