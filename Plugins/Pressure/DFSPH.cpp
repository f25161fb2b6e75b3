#include "Plugins/Pressure/DFSPH.h"

#include "Plugins/Pressure/PackedPairSums.h"
#include "Plugins/Pressure/SphPressureTerms.h"
#include "Simulation/ParamBinding.h"
#include "Simulation/PluginRegistry.h"
#include "Utilities/ParallelFor.h"

namespace consph {

namespace {
const PluginRegistration<PressureSolver> registration{
    "DFSPH", "Divergence-free SPH: constant-density and divergence-free solves (Bender & Koschier 2017)",
    DFSPH::parameters(), [](const Params& p, const PluginContext& c) -> std::unique_ptr<PressureSolver> {
      return std::make_unique<DFSPH>(p, *c.fluid, c.boundaryPressure);
    }};

// Particles with fewer neighbours sit at the free surface: their divergence is not enforced.
constexpr Index kMinNeighborsForDivergence = 20;
// A squeeze (BoundaryPressureTreatment::squeeze) above this marks a closing gap: between two
// walls at right angles it is 1 - 1/sqrt(2) = 0.29, between faces opposite each other near 1.
constexpr Real kClosingGapSqueeze = Real(0.5);
}  // namespace

const BoundParams<DFSPH::Settings>& DFSPH::bound() {
  static const BoundParams<Settings> table{
      bindPercent({"maxError", ParamType::Real, 0.01, "tolerated average compression of the density solve, % of rho0", 1e-6, 100},
                  &Settings::maxError),
      bindChoice<Settings>(
          {"bodyCoupling", ParamType::String, "auto",
           "how dynamic bodies enter the solve: iterated (their samples move, between iterations, as the impulses so far "
           "would move them: Simulation/BodyResponse.h), explicit (they move only after the solve), or auto: iterated "
           "with sample layers (Akinci2012), explicit with volume maps (measured: docs/rigid-bodies.md)",
           -std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(), {"auto", "explicit", "iterated"}},
          [](Settings& s, const std::string& v) {
            s.bodyCoupling = v == "iterated" ? BodyCoupling::Iterated : v == "explicit" ? BodyCoupling::Explicit : BodyCoupling::Auto;
          }),
      bindPercent({"maxErrorParticle", ParamType::Real, 1.0,
                   "the largest compression any one particle may keep, % of rho0: the density solve goes on (up to "
                   "maxIterations) until every particle is within it, not only the average within maxError; a particle "
                   "in a closing gap (two objects closing in from opposite sides) counts in the average only (under the "
                   "average alone, particles in a volume map's corner reached 2.5 rho0 and passed through the wall; held "
                   "to 1 % itself, the fluid under a box landing flat was thrown at 17 m/s: bench/RESULTS.md). 0: the "
                   "average alone (SPlisHSPlasH)",
                   0, 100},
                  &Settings::maxErrorParticle),
      bindPercent({"maxErrorDivergence", ParamType::Real, 0.1, "tolerated average divergence error, % of rho0 per step", 1e-6, 100},
                  &Settings::maxErrorDivergence),
      bind({"minIterations", ParamType::Int, 2, "minimum iterations of the density solve", 0, 10000}, &Settings::minIterations),
      bind({"maxIterations", ParamType::Int, 100, "maximum iterations of the density solve", 1, 100000}, &Settings::maxIterations),
      bind({"maxIterationsDivergence", ParamType::Int, 100, "maximum iterations of the divergence solve", 1, 100000},
           &Settings::maxIterationsDivergence),
      bind({"enableDivergenceSolver", ParamType::Bool, true, "run the divergence-free solve"}, &Settings::divergenceSolver),
      bind({"warmStart", ParamType::Bool, true, "start both solves from the previous step's pressures"}, &Settings::warmStart),
      bind(overlapReliefParameter(), &Settings::overlapReliefSpeed),
      bindChoice<Settings>(densityRelaxationParameter(),
                           [](Settings& s, const std::string& v) { s.densityRelaxation = densityRelaxationOf(v); }),
  };
  return table;
}

std::vector<ParamSpec> DFSPH::parameters() { return bound().specs(); }

DFSPH::DFSPH(const Params& p, FluidModel& fluid, BoundaryPressure treatment)
    : densityBeta_(fluid.fields().add<Real>("dfsphDensityBeta", FieldSorted, Real(0))),
      divergenceBeta_(fluid.fields().add<Real>("dfsphDivergenceBeta", FieldSorted, Real(0))),
      treatment_(treatment) {
  bound().assign(p, settings_);
  if (settings_.minIterations > settings_.maxIterations)
    throw InputError(p.pathOf("minIterations") + ": must not exceed maxIterations");
  if (settings_.maxErrorParticle > 0) treatment_.keepSqueeze();  // closingGap_ (computeDiagonal)
  treatment_.keepSampleFlux();  // computeSources' boundary part
}

void DFSPH::computeDiagonal(StepContext& ctx) {
  // D_i = |sum_j m_j grad W_ij + sum_k m~_k grad W_ik|^2 + sum_j m_i m_j |grad W_ij|^2   (Eq. 32)
  // mirroring and extrapolation add sum_k m_i m~_k |grad W_ik|^2                          (Eq. 15)
  treatment_.beginStep(ctx);
  const std::size_t n = ctx.fluid.size();
  // The slots of this step's packed pair sums (PackedPairSums.h): positions stay fixed through
  // both solves, and so does the fluid's gradient sum G_i (of the pressure term and the density
  // rate).
  if constexpr (kPackedPairSums) {
    ctx.paddedFluidNeighbors.expectBuiltFor(n, "DFSPH");
    packed_.packPositions(ctx.fluid);
    massGradientSums_.resize(n);
  }
  invDiagonal_.resize(n);
  increment_.resize(n);
  parallelFor(ctx.fluidNeighbors.work, n, [&](std::size_t i) {
    Real sumSquares = treatment_.diagonalTerm(i);
    Vector3r sumGrad;
    if constexpr (kPackedPairSums) {
      Vector3r fluidGradient = Vector3r::Zero();
      fluidDiagonalSums(ctx, i, fluidGradient, sumSquares);
      massGradientSums_[i] = fluidGradient;
      sumGrad = treatment_.boundaryGradient(i) + fluidGradient;
    } else {
      sumGrad = treatment_.boundaryGradient(i);
      fluidDiagonalSums(ctx, i, sumGrad, sumSquares);
    }
    const Real d = sumGrad.squaredNorm() + sumSquares;
    invDiagonal_[i] = d > Real(1e-9) ? Real(1) / d : Real(0);
  });
  // maxErrorParticle leaves out a particle in a closing gap (squeeze above that of two walls
  // at right angles, 1 - 1/sqrt(2) = 0.29; towards 1 between faces closing from opposite
  // sides): its compression can only go where the gap squeezes it out, at the gap's closing
  // rate times its length over its width, and holding it within 1 % threw the fluid under a box
  // landing flat at 17 m/s (RigidBodies.ASinkingBoxLandingFlatRestsAtTheDefaultStep). The
  // average still counts it.
  if (settings_.maxErrorParticle > 0) {
    closingGap_.resize(n);
    parallelFor(n, [&](std::size_t i) { closingGap_[i] = treatment_.squeeze(i) > kClosingGapSqueeze; });
  }
}

Real DFSPH::computeSources(StepContext& ctx, bool divergence, Real* largest) {
  const FluidView& f = ctx.fluid;
  const auto& fn = ctx.fluidNeighbors;
  const auto& bn = ctx.boundaryNeighbors;
  const Real rho0 = f.density0(), dt = ctx.dt;
  const std::size_t n = f.size();
  const Real maxDrop = maxDensityDrop(ctx, rho0, settings_.overlapReliefSpeed);
  const Real relaxationTime = densityRelaxationTime(settings_.densityRelaxation, ctx);
  if (kPackedPairSums && !velocitiesPacked_) packed_.packMomenta(f), velocitiesPacked_ = true;
  // The boundary's part from the step's gradient sums (one dot product per particle), unless the
  // bodies' samples move between iterations: then over the pairs, with their velocities now.
  const bool samplesFixed = !iteratesBodies(ctx);
  // The sum per range of the lists' balanced schedule, and the largest.
  struct Errors {
    double sum = 0;
    Real largest = 0;
  };
  const Errors errors = parallelReduce(
      fn.work, n, Errors{}, [](Errors& into, const Errors& from) { into.sum += from.sum, into.largest = std::max(into.largest, from.largest); },
      [&](std::size_t i, Errors& acc) {
        // Eqs. (6), (14)
        const Real fluidRate =
            kPackedPairSums ? packedFluidDensityRate(ctx.paddedFluidNeighbors, i, packed_, f, massGradientSums_[i]) : fluidDensityRate(ctx, i);
        const Real drho = samplesFixed ? fluidRate + treatment_.densityRate(i, f.velocities[i]) : boundaryDensityRate(ctx, i, fluidRate);
        Real s;
        if (divergence) {
          // Only compression counts, and not at the free surface.
          s = std::max(drho, Real(0));
          if (fn.count(i) + bn.count(i) < kMinNeighborsForDivergence) s = 0;
          increment_[i] = s * invDiagonal_[i] / dt;
          acc.sum += double(s * dt / rho0);
        } else {
          // rho*_i - target with rho*_i = rho_i + dt D rho_i / Dt (Eq. 6), compression only.
          const Real target = driftTarget(f.densities[i], rho0, dt, relaxationTime, maxDrop);
          s = std::max(f.densities[i] + dt * drho - target, Real(0));
          increment_[i] = s * invDiagonal_[i] / (dt * dt);
          acc.sum += double(s / rho0);
          if (settings_.maxErrorParticle <= 0 || !closingGap_[i]) acc.largest = std::max(acc.largest, s / rho0);
        }
      });
  if (largest) *largest = errors.largest;
  return n ? Real(errors.sum / double(n)) : Real(0);
}

void DFSPH::applyPressureIncrement(StepContext& ctx, const std::vector<Real>& k, std::vector<Real>* accumulated) {
  const FluidView& f = ctx.fluid;
  const Real dt = ctx.dt;
  // Extrapolation: p_k from the pressures after this increment, p_j = (beta_j + k_j) rho_j^2;
  // the velocities already carry the previously applied p_k, so only its change is applied.
  if (treatment_.extrapolates())
    treatment_.extrapolate([&](Index j) { return ((accumulated ? (*accumulated)[j] : Real(0)) + k[j]) * f.densities[j] * f.densities[j]; });
  const std::vector<Real>& pkChange = treatment_.boundaryPressureChanges();
  if constexpr (kPackedPairSums) {
    packed_.packPressures(f, k.data());
    packed_.momenta.resize(4 * f.size());  // every slot is written below
  }
  parallelFor(ctx.fluidNeighbors.work, f.size(), [&](std::size_t i) {
    const Real ki = k[i];
    Vector3r dv = kPackedPairSums ? packedFluidPressureAcceleration(ctx.paddedFluidNeighbors, i, packed_, ki, massGradientSums_[i])
                                  : fluidPressureAcceleration(ctx, i, k);  // Eq. (9) / (24)
    // Boundary: Eq. (33) (consistent) or Eq. (16) (mirroring, extrapolation).
    dv += treatment_.acceleration(ctx, i, ki, ki * f.densities[i] * f.densities[i], pkChange);
    f.velocities[i] += dt * dv;
    if constexpr (kPackedPairSums) packed_.setMomentum(&packed_.momenta[4 * i], f, i);
    // Nothing in this loop reads the accumulated beta (the extrapolation read it above).
    if (accumulated) (*accumulated)[i] += ki;
  });
  velocitiesPacked_ = kPackedPairSums;
}

void DFSPH::warmStart(StepContext& ctx, std::vector<Real>& beta, Real dtScale) {
  const std::size_t n = ctx.fluid.size();
  treatment_.resetBoundaryPressures();
  if (!settings_.warmStart) {
    std::fill(beta.begin(), beta.begin() + n, Real(0));
    return;
  }
  // Half of last step's pressure: the sources count compression only, so an overshoot could
  // not be undone by the iterations.
  const Real scale = Real(0.5) * dtScale;
  parallelFor(n, [&](std::size_t i) { beta[i] *= scale; });
  applyPressureIncrement(ctx, beta, nullptr);
}

void DFSPH::beforeNonPressureForces(StepContext& ctx) {
  stats_ = PressureSolverStats();
  velocitiesPacked_ = false;  // the last step's solve and advection changed them
  computeDiagonal(ctx);
  divergenceDt_ = 0;
  if (!settings_.divergenceSolver) return;
  // The step size of this step is not chosen yet: the divergence solve runs with the last one.
  ctx.dt = ctx.dtPrevious;
  warmStart(ctx, divergenceBeta_, Real(1));
  letBodiesRespond(ctx, false);
  Real error = computeSources(ctx, true);
  int it = 0;
  while ((error > settings_.maxErrorDivergence || it < 1) && it < settings_.maxIterationsDivergence) {
    applyPressureIncrement(ctx, increment_, &divergenceBeta_);  // and divergenceBeta_ += increment_
    letBodiesRespond(ctx, false);
    error = computeSources(ctx, true);
    ++it;
  }
  if (iteratesBodies(ctx)) ctx.bodies->restore(ctx.boundary);
  stats_.divergenceIterations = it;
  stats_.divergenceError = error;
  divergenceDt_ = ctx.dt;
  if (treatment_.extrapolates()) divergenceBoundaryP_ = treatment_.boundaryPressures();
}

void DFSPH::solve(StepContext& ctx) {
  const FluidView& f = ctx.fluid;
  const std::size_t n = f.size();
  velocitiesPacked_ = false;  // the non-pressure forces changed them
  // beta of the density solve scales with 1 / dt^2.
  warmStart(ctx, densityBeta_, (ctx.dtPrevious * ctx.dtPrevious) / (ctx.dt * ctx.dt));
  letBodiesRespond(ctx, true);
  // The average compression within maxError and, with maxErrorParticle, every particle's within
  // it: the average alone let a few particles in a volume map's corner keep 1-2.5 rho0 for 0.2 s
  // until they passed through the wall (bench/RESULTS.md, issue 15).
  Real largest = 0;
  Real error = computeSources(ctx, false, &largest);
  auto converged = [&] {
    return error <= settings_.maxError && (settings_.maxErrorParticle <= 0 || largest <= settings_.maxErrorParticle);
  };
  int it = 0;
  while ((!converged() || it < settings_.minIterations) && it < settings_.maxIterations) {
    applyPressureIncrement(ctx, increment_, &densityBeta_);  // and densityBeta_ += increment_
    letBodiesRespond(ctx, true);
    error = computeSources(ctx, false, &largest);
    ++it;
  }
  if (iteratesBodies(ctx)) ctx.bodies->restore(ctx.boundary);
  stats_.pressureIterations = it;
  stats_.densityError = error;
  stats_.largestDensityError = largest;
  stats_.hitIterationCap = error > settings_.maxError && it >= settings_.maxIterations;
  // The pressure of the step is what both solves applied: p_i = beta_i rho_i^2 with the
  // divergence solve's beta (applied over its dt) converted to this step's dt. In a resting
  // column the divergence solve carries a share of the weight, so leaving it out reads low.
  const Real divergenceScale = divergenceDt_ / ctx.dt;
  parallelFor(n, [&](std::size_t i) {
    f.pressures[i] = (densityBeta_[i] + divergenceScale * divergenceBeta_[i]) * f.densities[i] * f.densities[i];
  });
}

void DFSPH::boundaryImpulses(const StepContext& ctx, std::vector<Vector3r>& impulsePerPair) const {
  // Without a divergence solve this step (disabled, or nothing to solve) its share is zero and
  // its boundary pressures were never recorded.
  const bool withDivergence = divergenceDt_ > 0;
  const std::vector<Real>& divergenceP =
      treatment_.extrapolates() && withDivergence ? divergenceBoundaryP_ : treatment_.boundaryPressures();
  pairImpulses(ctx, divergenceDt_, divergenceP, true, impulsePerPair);
}

bool DFSPH::iteratesBodies(const StepContext& ctx) const {
  // "auto": with volume maps the iterated form landed a box worse than the explicit one
  // (measured 2026-12-02, docs/rigid-bodies.md: one virtual sample per fluid particle carries
  // a body's whole wall there, and the trial motion it feeds back is not yet understood).
  if (!ctx.bodies) return false;
  return settings_.bodyCoupling == BodyCoupling::Iterated || (settings_.bodyCoupling == BodyCoupling::Auto && !ctx.implicitBoundary);
}

void DFSPH::letBodiesRespond(StepContext& ctx, bool densitySolve) {
  if (!iteratesBodies(ctx)) return;
  // During the divergence solve (run with the last step's dt) only its own impulses count, and
  // gravity has not acted yet; during the density solve both solves' and this step's gravity.
  // Only the pairs with a moving sample (a small share: the walls' pairs are skipped).
  const FluidView& f = ctx.fluid;
  const std::vector<MovingPair>& pairs = ctx.bodies->movingPairs(ctx.boundaryNeighbors, f.positions, f.masses, ctx.boundary);
  const Real divergenceDt = densitySolve ? divergenceDt_ : ctx.dt;
  const std::vector<Real>& divergenceP =
      densitySolve && treatment_.extrapolates() && divergenceDt_ > 0 ? divergenceBoundaryP_ : treatment_.boundaryPressures();
  trialImpulses_.resize(pairs.size());
  parallelFor(pairs.size(), [&](std::size_t p) {
    trialImpulses_[p] = pairImpulse(ctx, pairs[p].fluid, pairs[p].pair, divergenceDt, divergenceP, densitySolve);
  });
  ctx.bodies->respond(f.positions, trialImpulses_, densitySolve ? ctx.gravity : Vector3r::Zero(), ctx.dt, ctx.boundary);
}

void DFSPH::pairImpulses(const StepContext& ctx, Real divergenceDt, const std::vector<Real>& divergenceP, bool withDensity,
                         std::vector<Vector3r>& impulsePerPair) const {
  // Every application of the boundary term (warm start and each iteration, both solves) changed
  // v_i by -dt m~_k b_ik grad W_ik with this step's fixed gradients and densities, and b_ik is
  // linear in the applied beta_i and p_k, so the applications of one solve add up to its
  // accumulated values: the reaction on k is Eq. (35),
  // m_i m~_k (dt_div b_ik(divergence totals) + dt b_ik(density totals)) grad W_ik.
  const auto& bn = ctx.boundaryNeighbors;
  impulsePerPair.resize(bn.pairCount());
  parallelFor(ctx.fluid.size(), [&](std::size_t i) {
    for (Index e = bn.begin(i); e < bn.end(i); ++e) impulsePerPair[e] = pairImpulse(ctx, Index(i), e, divergenceDt, divergenceP, withDensity);
  });
}

}  // namespace consph
