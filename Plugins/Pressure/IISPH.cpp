#include "Plugins/Pressure/IISPH.h"

#include "Plugins/Pressure/SphPressureTerms.h"
#include "Simulation/ParamBinding.h"
#include "Simulation/PluginRegistry.h"
#include "Utilities/ParallelFor.h"

namespace consph {

namespace {
const PluginRegistration<PressureSolver> registration{
    "IISPH", "Implicit incompressible SPH: relaxed Jacobi on the pressure Poisson equation (Ihmsen et al. 2014)",
    IISPH::parameters(), [](const Params& p, const PluginContext& c) -> std::unique_ptr<PressureSolver> {
      return std::make_unique<IISPH>(p, c.boundaryPressure);
    }};
}  // namespace

const BoundParams<IISPH::Settings>& IISPH::bound() {
  static const BoundParams<Settings> table{
      bindPercent({"maxError", ParamType::Real, 0.01, "tolerated average predicted compression, % of rho0", 1e-6, 100},
                  &Settings::maxError),
      bind({"minIterations", ParamType::Int, 2, "minimum Jacobi iterations", 0, 10000}, &Settings::minIterations),
      bind({"maxIterations", ParamType::Int, 100, "maximum Jacobi iterations", 1, 100000}, &Settings::maxIterations),
      bind({"omega", ParamType::Real, 0.5, "relaxation factor of the Jacobi iteration (Eq. 11)", 1e-3, 1}, &Settings::omega),
      bind({"warmStart", ParamType::Bool, true, "start from half of the previous step's pressure"}, &Settings::warmStart),
      bind(overlapReliefParameter(), &Settings::overlapReliefSpeed),
      bindChoice<Settings>(densityRelaxationParameter(),
                           [](Settings& s, const std::string& v) { s.densityRelaxation = densityRelaxationOf(v); }),
  };
  return table;
}

std::vector<ParamSpec> IISPH::parameters() { return bound().specs(); }

IISPH::IISPH(const Params& p, BoundaryPressure treatment) : treatment_(treatment) {
  bound().assign(p, settings_);
  if (settings_.minIterations > settings_.maxIterations)
    throw InputError(p.pathOf("minIterations") + ": must not exceed maxIterations");
}

void IISPH::prepare(StepContext& ctx) {
  treatment_.beginStep(ctx);
  if (treatment_.extrapolates()) treatment_.computeExtrapolationCoupling(ctx);
  const FluidView& f = ctx.fluid;
  const Real rho0 = f.density0(), dt = ctx.dt, omega = settings_.omega;
  const Real start = settings_.warmStart ? Real(0.5) : Real(0);
  const Real relaxationTime = densityRelaxationTime(settings_.densityRelaxation, ctx);
  const Real maxDrop = maxDensityDrop(ctx, rho0, settings_.overlapReliefSpeed);
  const std::size_t n = f.size();
  source_.resize(n);
  omegaOverA_.resize(n);
  beta_.resize(n);
  pressureAcc_.resize(n);
  parallelFor(ctx.fluidNeighbors.work, n, [&](std::size_t i) {
    const Real rhoI = f.densities[i];
    // s_i = (target - rho*_i) / dt, rho*_i = rho_i + dt D rho_i / Dt (Eqs. 5, 6); target = rho0
    // unless the step starts over rho0 (driftTarget, overlap relief).
    const Real target = driftTarget(rhoI, rho0, dt, relaxationTime, maxDrop);
    source_[i] = (target - rhoI - dt * densityRate(ctx, i)) / dt;
    // A_ii = -dt / rho_i^2 (|sum_j m_j grad W_ij + g_i|^2 + sum_j m_i m_j |grad W_ij|^2 [+ Eq. 15's term]).
    Vector3r sumGrad = treatment_.boundaryGradient(i);
    Real squares = treatment_.extrapolates() ? Real(0) : treatment_.diagonalTerm(i);
    fluidDiagonalSums(ctx, i, sumGrad, squares);
    if (treatment_.extrapolates()) squares += treatment_.extrapolationDiagonalTerm(i, sumGrad, rhoI);
    const Real d = sumGrad.squaredNorm() + squares;
    omegaOverA_[i] = d > Real(1e-9) ? -omega * rhoI * rhoI / (dt * d) : Real(0);
    f.pressures[i] = omegaOverA_[i] != 0 ? start * f.pressures[i] : Real(0);
    beta_[i] = f.pressures[i] / (rhoI * rhoI);
  });
}

void IISPH::computeAccelerations(StepContext& ctx) {
  const FluidView& f = ctx.fluid;
  if (treatment_.extrapolates()) treatment_.extrapolate([&](Index j) { return f.pressures[j]; });
  const std::vector<Real>& pk = treatment_.boundaryPressures();
  parallelFor(ctx.fluidNeighbors.work, f.size(), [&](std::size_t i) {
    pressureAcc_[i] = fluidPressureAcceleration(ctx, i, beta_) + treatment_.acceleration(ctx, i, beta_[i], f.pressures[i], pk);
  });
}

Real IISPH::jacobiSweep(StepContext& ctx) {
  const FluidView& f = ctx.fluid;
  const NeighborLists& fn = ctx.fluidNeighbors;
  const Real rho0 = f.density0(), dt = ctx.dt;
  const std::size_t n = f.size();
  const double errorSum = parallelSum<double>(fn.work, n, [&](std::size_t i) {
    // (A p)_i = dt (sum_j m_j (a_i - a_j) . grad W_ij + sum_k m~_k (a_i - a_k) . grad W_ik) with
    // a_k = 0 (Eqs. 10, 17, 34): the boundary sum is a_i . g_i.
    const Vector3r ai = pressureAcc_[i], xi = f.positions[i];
    Real laplacian = ai.dot(treatment_.boundaryGradient(i));
    for (Index e = fn.begin(i); e < fn.end(i); ++e) {
      const Index j = fn.indices[e];
      laplacian += f.masses[j] * (ai - pressureAcc_[j]).dot(fn.gradient(e, xi - f.positions[j]));
    }
    const Real residual = source_[i] - dt * laplacian;
    // rho**_i - rho0 = -dt residual_i: the compression these pressures leave.
    const Real compression = std::max(-dt * residual, Real(0)) / rho0;
    // Eq. (11), clamped: negative pressures would pull the free surface together.
    const Real p = std::max(f.pressures[i] + omegaOverA_[i] * residual, Real(0));
    f.pressures[i] = p;
    beta_[i] = p / (f.densities[i] * f.densities[i]);
    return compression;
  });
  return n ? Real(errorSum / double(n)) : Real(0);
}

void IISPH::solve(StepContext& ctx) {
  stats_ = PressureSolverStats();
  prepare(ctx);
  Real error = 0;
  int it = 0;
  do {
    computeAccelerations(ctx);
    error = jacobiSweep(ctx);
    ++it;
  } while ((error > settings_.maxError || it < settings_.minIterations) && it < settings_.maxIterations);
  stats_.pressureIterations = it;
  stats_.densityError = error;
  stats_.hitIterationCap = error > settings_.maxError && it >= settings_.maxIterations;
  // v(t + dt) = v* + dt a^p with the final pressures.
  computeAccelerations(ctx);
  const FluidView& f = ctx.fluid;
  const Real dt = ctx.dt;
  parallelFor(f.size(), [&](std::size_t i) { f.velocities[i] += dt * pressureAcc_[i]; });
}

void IISPH::boundaryImpulses(const StepContext& ctx, std::vector<Vector3r>& impulsePerPair) const {
  // The fluid received dt a^p once, with the final pressures: the reaction on k, Eq. (35).
  treatment_.reactionImpulses(ctx, ctx.dt, beta_, ctx.fluid.pressures, impulsePerPair);
}

}  // namespace consph
