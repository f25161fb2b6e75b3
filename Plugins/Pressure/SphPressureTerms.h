// The SPH sums every pressure solver evaluates per fluid particle i (Bender, Westhofen, Jeske
// 2023, Section 3.2), inline so that they sit inside the solvers' OpenMP loops.
#pragma once
#include <algorithm>
#include <limits>
#include <string>

#include "Simulation/Params.h"
#include "Simulation/StepContext.h"

namespace consph {

// D rho_i / Dt = sum_j m_j (v_i - v_j) . grad W_ij + sum_k m~_k (v_i - v_k) . grad W_ik
// (Eqs. 6 and 14), from the current velocities (v* in the density solve): the fluid sum, then
// the boundary sum added on to `rate` (PackedPairSums.h has a second form of the fluid sum).
inline Real fluidDensityRate(const StepContext& ctx, std::size_t i) {
  const FluidView& f = ctx.fluid;
  const NeighborLists& fn = ctx.fluidNeighbors;
  const Vector3r vi = f.velocities[i], xi = f.positions[i];
  Real rate = 0;
  for (Index e = fn.begin(i); e < fn.end(i); ++e) {
    const Index j = fn.indices[e];
    rate += f.masses[j] * (vi - f.velocities[j]).dot(fn.gradient(e, xi - f.positions[j]));
  }
  return rate;
}
inline Real boundaryDensityRate(const StepContext& ctx, std::size_t i, Real rate) {
  const BoundaryView& b = ctx.boundary;
  const NeighborLists& bn = ctx.boundaryNeighbors;
  const Vector3r vi = ctx.fluid.velocities[i];
  for (Index e = bn.begin(i); e < bn.end(i); ++e) rate += b.masses[bn.indices[e]] * (vi - b.velocities[bn.indices[e]]).dot(bn.gradW[e]);
  return rate;
}
inline Real densityRate(const StepContext& ctx, std::size_t i) { return boundaryDensityRate(ctx, i, fluidDensityRate(ctx, i)); }

// How fast the implicit solvers remove a density excess a step starts with (driftTarget).
enum class DensityRelaxation { Auto, Step, Resolution };

// The parameter both implicit solvers declare for it.
inline ParamSpec densityRelaxationParameter() {
  return {"densityRelaxation", ParamType::String, "auto",
          "how fast a density excess a step starts with is removed: step (within every step taken, the classical "
          "form; its correction velocity grows as 1 / dt when the step is lowered by hand), resolution (over the step "
          "the resolution calls for, StepContext::densityRelaxationTime, so the motion converges as the step is "
          "lowered), or auto: resolution with sampled walls (Akinci2012), step with volume maps, where a box landing "
          "on the floor with resolution threw a particle through it (docs/boundary-pressure.md)",
          -std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(), {"auto", "resolution", "step"}};
}
inline DensityRelaxation densityRelaxationOf(const std::string& v) {
  return v == "resolution" ? DensityRelaxation::Resolution : v == "step" ? DensityRelaxation::Step : DensityRelaxation::Auto;
}

// The time T over which this step's density excess is removed: the resolution's step, or 0 for
// within the step ("auto" resolved by the boundary model).
inline Real densityRelaxationTime(DensityRelaxation mode, const StepContext& ctx) {
  const bool overResolutionStep =
      mode == DensityRelaxation::Resolution || (mode == DensityRelaxation::Auto && !ctx.implicitBoundary);
  return overResolutionStep ? ctx.densityRelaxationTime : Real(0);
}

// The parameter both implicit solvers declare for pushing an overlap apart at a bounded speed.
inline ParamSpec overlapReliefParameter() {
  return {"overlapReliefSpeed", ParamType::Real, 0.25,
          "overlap relief: a particle more than 1 % over rho0 at the start of a step (an overlap with a body, a start "
          "lattice packed against a volume map's edge) is asked to lose at most rho0 overlapReliefSpeed dt / h of "
          "density per step instead of all of it, which would fling it out; measured push-out speeds are about 4 "
          "times this, m/s (0: off)",
          0, 1e6};
}

// Overlap relief: the most density a step may ask a particle to lose, rho0 speed dt / h, but never
// under 1 % of rho0 so that particles within 1 % (every particle of a converged run) keep the
// target rho0. Without it an overlap is removed within one step, at about (overlap depth) / dt,
// more where grad W vanishes near a sample: IISPH's tank at r = 0.0125 on volume maps starts 28 %
// over rho0 at the edges and blew up in its fourth step.
inline Real maxDensityDrop(const StepContext& ctx, Real rho0, Real overlapReliefSpeed) {
  if (overlapReliefSpeed <= 0) return std::numeric_limits<Real>::infinity();
  return std::max(rho0 * overlapReliefSpeed * ctx.dt / ctx.kernel.supportRadius(), Real(0.01) * rho0);
}

// The density rho_i is asked to reach by the end of the step (the solves' rho0 in Eq. 5): rho0
// where the step starts at or under rho0. A particle that starts over rho0 carries drift (the
// tolerance the previous solves left, the start lattice's own error, an overlap): rho*_i = rho0
// would take the whole excess out within this step, at a velocity of about excess h / (rho0 dt),
// which grows without bound as the step shrinks and gives a dam break 20 % more energy than it
// started with at a tenth of the default step. Instead the excess decays over the relaxation
// time T (a Baumgarte-style stabilisation): a fraction min(1, dt / T) of it per step, and at most
// maxDrop (overlap relief); with T = 0 (densityRelaxation "step") it is all of it, as before.
inline Real driftTarget(Real rho, Real rho0, Real dt, Real relaxationTime, Real maxDrop) {
  const Real excess = rho - rho0;
  if (excess <= 0) return rho0;
  const Real fraction = relaxationTime > dt ? dt / relaxationTime : Real(1);
  return rho - std::min(fraction * excess, maxDrop);
}

// Fluid part of the pressure acceleration, Eq. (9) written with beta = p / rho^2 (= lambda / rho,
// Eq. 24): -sum_j m_j (beta_i + beta_j) grad W_ij.
inline Vector3r fluidPressureAcceleration(const StepContext& ctx, std::size_t i, const std::vector<Real>& beta) {
  const FluidView& f = ctx.fluid;
  const NeighborLists& fn = ctx.fluidNeighbors;
  const Real bi = beta[i];
  const Vector3r xi = f.positions[i];
  Vector3r a = Vector3r::Zero();
  for (Index e = fn.begin(i); e < fn.end(i); ++e) {
    const Index j = fn.indices[e];
    a -= f.masses[j] * (bi + beta[j]) * fn.gradient(e, xi - f.positions[j]);
  }
  return a;
}

// sum_j m_j |grad W_ij|^2 m_i (Eq. 12) and the gradient sum sum_j m_j grad W_ij, for the diagonal.
inline void fluidDiagonalSums(const StepContext& ctx, std::size_t i, Vector3r& gradientSum, Real& squares) {
  const FluidView& f = ctx.fluid;
  const NeighborLists& fn = ctx.fluidNeighbors;
  const Real mi = f.masses[i];
  const Vector3r xi = f.positions[i];
  for (Index e = fn.begin(i); e < fn.end(i); ++e) {
    const Index j = fn.indices[e];
    const Real mj = f.masses[j];
    const Vector3r g = fn.gradient(e, xi - f.positions[j]);
    gradientSum += mj * g;
    squares += mi * mj * g.squaredNorm();
  }
}

}  // namespace consph
