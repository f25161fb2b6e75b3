#include "Plugins/Pressure/DFSPH.h"

#include "Simulation/PluginRegistry.h"

namespace consph {

namespace {
const PluginRegistration<PressureSolver> registration{
    "DFSPH", "Divergence-free SPH: constant-density and divergence-free solves (Bender & Koschier 2017)",
    DFSPH::parameters(), [](const Params& p, const PluginContext& c) -> std::unique_ptr<PressureSolver> {
      return std::make_unique<DFSPH>(p, *c.fluid);
    }};

// Particles with fewer neighbours sit at the free surface: their divergence is not enforced.
constexpr Index kMinNeighborsForDivergence = 20;
}  // namespace

std::vector<ParamSpec> DFSPH::parameters() {
  return {
      {"maxError", ParamType::Real, 0.01, "tolerated average compression of the density solve, % of rho0", 1e-6, 100},
      {"maxErrorDivergence", ParamType::Real, 0.1, "tolerated average divergence error, % of rho0 per step", 1e-6, 100},
      {"minIterations", ParamType::Int, 2, "minimum iterations of the density solve", 0, 10000},
      {"maxIterations", ParamType::Int, 100, "maximum iterations of the density solve", 1, 100000},
      {"maxIterationsDivergence", ParamType::Int, 100, "maximum iterations of the divergence solve", 1, 100000},
      {"enableDivergenceSolver", ParamType::Bool, true, "run the divergence-free solve"},
      {"warmStart", ParamType::Bool, true, "start both solves from the previous step's pressures"},
      {"overlapReliefSpeed", ParamType::Real, 0.25,
       "overlap relief: a particle more than 1 % over rho0 at the start of a step (an overlap with a body) "
       "is asked to lose at most rho0 overlapReliefSpeed dt / h of density per step instead of all of it, "
       "which would fling it out; measured push-out speeds are about 4 times this, m/s (0: off)", 0, 1e6},
  };
}

DFSPH::DFSPH(const Params& p, FluidModel& fluid)
    : densityBeta_(fluid.fields().add<Real>("dfsphDensityBeta", FieldSorted, Real(0))),
      divergenceBeta_(fluid.fields().add<Real>("dfsphDivergenceBeta", FieldSorted, Real(0))) {
  settings_.maxError = p.real("maxError") / 100;
  settings_.maxErrorDivergence = p.real("maxErrorDivergence") / 100;
  settings_.minIterations = p.integer("minIterations");
  settings_.maxIterations = p.integer("maxIterations");
  settings_.maxIterationsDivergence = p.integer("maxIterationsDivergence");
  settings_.divergenceSolver = p.boolean("enableDivergenceSolver");
  settings_.warmStart = p.boolean("warmStart");
  settings_.overlapReliefSpeed = p.real("overlapReliefSpeed");
  if (settings_.minIterations > settings_.maxIterations)
    throw InputError(p.pathOf("minIterations") + ": must not exceed maxIterations");
}

void DFSPH::computeDiagonal(StepContext& ctx) {
  // D_i = |sum_j m_j grad W_ij + sum_k m~_k grad W_ik|^2 + sum_j m_i m_j |grad W_ij|^2   (Eq. 32)
  // mirroring adds sum_k m_i m~_k |grad W_ik|^2                                          (Eq. 15)
  FluidModel& f = ctx.fluid;
  const BoundarySamples& b = ctx.boundary;
  const auto& fn = ctx.fluidNeighbors;
  const auto& bn = ctx.boundaryNeighbors;
  const bool mirrored = ctx.boundaryPressure != BoundaryPressure::Consistent;
  const std::size_t n = f.size();
  invDiagonal_.resize(n);
  source_.resize(n);
  increment_.resize(n);
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t i = 0; i < std::ptrdiff_t(n); ++i) {
    Vector3r sumGrad = Vector3r::Zero();
    Real sumSquares = 0;
    const Real mi = f.masses[i];
    for (Index e = fn.begin(i); e < fn.end(i); ++e) {
      const Vector3r g = f.masses[fn.indices[e]] * fn.gradW[e];
      sumGrad += g;
      sumSquares += mi / f.masses[fn.indices[e]] * g.squaredNorm();
    }
    for (Index e = bn.begin(i); e < bn.end(i); ++e) {
      const Vector3r g = b.masses[bn.indices[e]] * bn.gradW[e];
      sumGrad += g;
      if (mirrored) sumSquares += mi / b.masses[bn.indices[e]] * g.squaredNorm();
    }
    const Real d = sumGrad.squaredNorm() + sumSquares;
    invDiagonal_[i] = d > Real(1e-9) ? Real(1) / d : Real(0);
  }
}

Real DFSPH::computeSources(StepContext& ctx, bool divergence) {
  FluidModel& f = ctx.fluid;
  const BoundarySamples& b = ctx.boundary;
  const auto& fn = ctx.fluidNeighbors;
  const auto& bn = ctx.boundaryNeighbors;
  const Real rho0 = f.density0(), dt = ctx.dt;
  const std::size_t n = f.size();
  // Overlap relief: the target density of a particle that is already far too dense (an overlap
  // with a body at start-up) is lowered by at most maxDensityDrop per step instead of to rho0
  // at once, which needs about (overlap depth) / dt, more where grad W vanishes near a sample.
  // Particles within 1 % of rho0 (every particle of a converged run) keep the target rho0.
  const Real maxDensityDrop = settings_.overlapReliefSpeed > 0
                                  ? std::max(rho0 * settings_.overlapReliefSpeed * dt / ctx.kernel.supportRadius(),
                                             Real(0.01) * rho0)
                                  : std::numeric_limits<Real>::infinity();
  double errorSum = 0;
#pragma omp parallel for schedule(static) reduction(+ : errorSum)
  for (std::ptrdiff_t i = 0; i < std::ptrdiff_t(n); ++i) {
    // D rho_i / Dt = sum_j m_j (v_i - v_j) . grad W_ij + sum_k m~_k (v_i - v_k) . grad W_ik
    const Vector3r vi = f.velocities[i];
    Real drho = 0;
    for (Index e = fn.begin(i); e < fn.end(i); ++e)
      drho += f.masses[fn.indices[e]] * (vi - f.velocities[fn.indices[e]]).dot(fn.gradW[e]);
    for (Index e = bn.begin(i); e < bn.end(i); ++e)
      drho += b.masses[bn.indices[e]] * (vi - b.velocities[bn.indices[e]]).dot(bn.gradW[e]);
    Real s;
    if (divergence) {
      // Only compression counts, and not at the free surface.
      s = std::max(drho, Real(0));
      if (fn.count(i) + bn.count(i) < kMinNeighborsForDivergence) s = 0;
      increment_[i] = s * invDiagonal_[i] / dt;
      errorSum += s * dt / rho0;
    } else {
      // rho*_i - rho0 with rho*_i = rho_i + dt D rho_i / Dt (Eq. 6), compression only.
      const Real target = std::max(rho0, f.densities[i] - maxDensityDrop);
      s = std::max(f.densities[i] + dt * drho - target, Real(0));
      increment_[i] = s * invDiagonal_[i] / (dt * dt);
      errorSum += s / rho0;
    }
    source_[i] = s;
  }
  return n ? Real(errorSum / double(n)) : Real(0);
}

Real DFSPH::boundaryFactor(const StepContext& ctx, std::size_t i) const {
  // Boundary: consistent, Eq. (33): m~_k lambda_i / rho_i = m~_k beta_i;
  // mirroring, Eq. (16) with p_k = p_i: m~_k p_i (1 / rho_i^2 + 1 / rho0^2).
  if (ctx.boundaryPressure != BoundaryPressure::Mirroring) return Real(1);
  const Real rhoRatio = ctx.fluid.densities[i] / ctx.fluid.density0();
  return Real(1) + rhoRatio * rhoRatio;
}

void DFSPH::applyPressureIncrement(StepContext& ctx, const std::vector<Real>& k) {
  FluidModel& f = ctx.fluid;
  const BoundarySamples& b = ctx.boundary;
  const auto& fn = ctx.fluidNeighbors;
  const auto& bn = ctx.boundaryNeighbors;
  const Real dt = ctx.dt;
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t i = 0; i < std::ptrdiff_t(f.size()); ++i) {
    const Real ki = k[i];
    Vector3r dv = Vector3r::Zero();
    for (Index e = fn.begin(i); e < fn.end(i); ++e) {
      const Index j = fn.indices[e];
      dv -= f.masses[j] * (ki + k[j]) * fn.gradW[e];
    }
    const Real kb = ki * boundaryFactor(ctx, i);
    for (Index e = bn.begin(i); e < bn.end(i); ++e) dv -= b.masses[bn.indices[e]] * kb * bn.gradW[e];
    f.velocities[i] += dt * dv;
  }
}

void DFSPH::warmStart(StepContext& ctx, std::vector<Real>& beta, Real dtScale) {
  const std::size_t n = ctx.fluid.size();
  if (!settings_.warmStart) {
    std::fill(beta.begin(), beta.begin() + n, Real(0));
    return;
  }
  // Half of last step's pressure: the sources count compression only, so an overshoot could
  // not be undone by the iterations.
  const Real scale = Real(0.5) * dtScale;
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t i = 0; i < std::ptrdiff_t(n); ++i) beta[i] *= scale;
  applyPressureIncrement(ctx, beta);
}

void DFSPH::beforeNonPressureForces(StepContext& ctx) {
  stats_ = PressureSolverStats();
  divergenceDt_ = 0;
  computeDiagonal(ctx);
  FluidModel& f = ctx.fluid;
  const std::size_t n = f.size();
  if (!settings_.divergenceSolver) return;
  // The step size of this step is not chosen yet: the divergence solve runs with the last one.
  ctx.dt = ctx.dtPrevious;
  divergenceDt_ = ctx.dt;
  warmStart(ctx, divergenceBeta_, Real(1));
  Real error = computeSources(ctx, true);
  int it = 0;
  while ((error > settings_.maxErrorDivergence || it < 1) && it < settings_.maxIterationsDivergence) {
    applyPressureIncrement(ctx, increment_);
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t i = 0; i < std::ptrdiff_t(n); ++i) divergenceBeta_[i] += increment_[i];
    error = computeSources(ctx, true);
    ++it;
  }
  stats_.divergenceIterations = it;
  stats_.divergenceError = error;
}

void DFSPH::solve(StepContext& ctx) {
  FluidModel& f = ctx.fluid;
  const std::size_t n = f.size();
  // beta of the density solve scales with 1 / dt^2.
  warmStart(ctx, densityBeta_, (ctx.dtPrevious * ctx.dtPrevious) / (ctx.dt * ctx.dt));
  Real error = computeSources(ctx, false);
  int it = 0;
  while ((error > settings_.maxError || it < settings_.minIterations) && it < settings_.maxIterations) {
    applyPressureIncrement(ctx, increment_);
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t i = 0; i < std::ptrdiff_t(n); ++i) densityBeta_[i] += increment_[i];
    error = computeSources(ctx, false);
    ++it;
  }
  stats_.pressureIterations = it;
  stats_.densityError = error;
  stats_.hitIterationCap = error > settings_.maxError && it >= settings_.maxIterations;
  // The pressure of the step is what both solves applied: p_i = beta_i rho_i^2 with the
  // divergence solve's beta (applied over dtPrevious) converted to this step's dt. In a resting
  // column the divergence solve carries a share of the weight, so leaving it out reads low.
  const Real divergenceScale = settings_.divergenceSolver ? ctx.dtPrevious / ctx.dt : Real(0);
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t i = 0; i < std::ptrdiff_t(n); ++i)
    f.pressures[i] = (densityBeta_[i] + divergenceScale * divergenceBeta_[i]) * f.densities[i] * f.densities[i];
}

void DFSPH::boundaryImpulses(const StepContext& ctx, std::vector<Vector3r>& impulsePerPair) const {
  // Every application of the boundary term (warm start and each iteration, both solves) changed
  // v_i by -dt m~_k factor_i beta grad W_ik with this step's fixed gradients and densities, so
  // the applications of one solve add up to its accumulated beta: the reaction on k is Eq. (35),
  // m_i m~_k factor_i (dt_div beta_div,i + dt beta_density,i) grad W_ik (beta_i = p_i / rho_i^2).
  const FluidModel& f = ctx.fluid;
  const BoundarySamples& b = ctx.boundary;
  const auto& bn = ctx.boundaryNeighbors;
  impulsePerPair.resize(bn.pairCount());
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t i = 0; i < std::ptrdiff_t(f.size()); ++i) {
    const Real c = f.masses[i] * boundaryFactor(ctx, i) * (divergenceDt_ * divergenceBeta_[i] + ctx.dt * densityBeta_[i]);
    for (Index e = bn.begin(i); e < bn.end(i); ++e) impulsePerPair[e] = (c * b.masses[bn.indices[e]]) * bn.gradW[e];
  }
}

}  // namespace consph
