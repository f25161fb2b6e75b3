#include "Plugins/Pressure/WCSPH.h"

#include <cmath>

#include "Simulation/PluginRegistry.h"

namespace consph {

namespace {
const PluginRegistration<PressureSolver> registration{
    "WCSPH", "Weakly compressible SPH with the Tait equation (Becker & Teschner 2007); needs small time steps",
    WCSPH::parameters(), [](const Params& p, const PluginContext&) -> std::unique_ptr<PressureSolver> {
      return std::make_unique<WCSPH>(p);
    }};
}  // namespace

std::vector<ParamSpec> WCSPH::parameters() {
  return {{"stiffness", ParamType::Real, 50000.0, "Tait stiffness k, Pa", 1e-6, 1e12},
          {"exponent", ParamType::Real, 7.0, "Tait exponent gamma", 1, 20}};
}

WCSPH::WCSPH(const Params& p) : stiffness_(p.real("stiffness")), exponent_(p.real("exponent")) {}

namespace {
// Boundary: Eq. (33) (consistent) or Eq. (16) with p_k = p_i (mirroring): a_i -= m~_k bb grad W_ik.
Real boundaryTerm(const FluidModel& f, std::size_t i, bool mirroring) {
  const Real bi = f.pressures[i] / (f.densities[i] * f.densities[i]);
  return mirroring ? bi + f.pressures[i] / (f.density0() * f.density0()) : bi;
}
}  // namespace

void WCSPH::solve(StepContext& ctx) {
  stats_ = PressureSolverStats();
  FluidModel& f = ctx.fluid;
  const BoundarySamples& b = ctx.boundary;
  const auto& fn = ctx.fluidNeighbors;
  const auto& bn = ctx.boundaryNeighbors;
  const Real rho0 = f.density0(), dt = ctx.dt;
  const std::ptrdiff_t n = std::ptrdiff_t(f.size());
  double errorSum = 0;
#pragma omp parallel for schedule(static) reduction(+ : errorSum)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    const Real ratio = f.densities[i] / rho0;
    f.pressures[i] = std::max(Real(0), stiffness_ * (std::pow(ratio, exponent_) - Real(1)));
    errorSum += std::max(ratio - Real(1), Real(0));
  }
  const bool mirroring = ctx.boundaryPressure != BoundaryPressure::Consistent;
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    const Real bi = f.pressures[i] / (f.densities[i] * f.densities[i]);
    Vector3r a = Vector3r::Zero();
    // Eq. (9)
    for (Index e = fn.begin(i); e < fn.end(i); ++e) {
      const Index j = fn.indices[e];
      a -= f.masses[j] * (bi + f.pressures[j] / (f.densities[j] * f.densities[j])) * fn.gradW[e];
    }
    const Real bb = boundaryTerm(f, i, mirroring);
    for (Index e = bn.begin(i); e < bn.end(i); ++e) a -= b.masses[bn.indices[e]] * bb * bn.gradW[e];
    f.velocities[i] += dt * a;
  }
  stats_.densityError = n ? Real(errorSum / double(n)) : Real(0);
}

void WCSPH::boundaryImpulses(const StepContext& ctx, std::vector<Vector3r>& impulsePerPair) const {
  // The reaction of the boundary term, Eq. (35): dt m_i m~_k bb_i grad W_ik.
  const FluidModel& f = ctx.fluid;
  const auto& bn = ctx.boundaryNeighbors;
  const bool mirroring = ctx.boundaryPressure != BoundaryPressure::Consistent;
  impulsePerPair.resize(bn.pairCount());
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t i = 0; i < std::ptrdiff_t(f.size()); ++i) {
    const Real c = ctx.dt * f.masses[i] * boundaryTerm(f, i, mirroring);
    for (Index e = bn.begin(i); e < bn.end(i); ++e) impulsePerPair[e] = (c * ctx.boundary.masses[bn.indices[e]]) * bn.gradW[e];
  }
}

}  // namespace consph
