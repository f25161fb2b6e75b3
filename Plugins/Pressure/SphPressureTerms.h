// The SPH sums every pressure solver evaluates per fluid particle i (Bender, Westhofen, Jeske
// 2023, Section 3.2), inline so that they sit inside the solvers' OpenMP loops.
#pragma once
#include "Simulation/StepContext.h"

namespace consph {

// D rho_i / Dt = sum_j m_j (v_i - v_j) . grad W_ij + sum_k m~_k (v_i - v_k) . grad W_ik
// (Eqs. 6 and 14), from the current velocities (v* in the density solve).
inline Real densityRate(const StepContext& ctx, std::size_t i) {
  const FluidModel& f = ctx.fluid;
  const BoundarySamples& b = ctx.boundary;
  const NeighborLists& fn = ctx.fluidNeighbors;
  const NeighborLists& bn = ctx.boundaryNeighbors;
  const Vector3r vi = f.velocities[i];
  Real rate = 0;
  for (Index e = fn.begin(i); e < fn.end(i); ++e) rate += f.masses[fn.indices[e]] * (vi - f.velocities[fn.indices[e]]).dot(fn.gradW[e]);
  for (Index e = bn.begin(i); e < bn.end(i); ++e) rate += b.masses[bn.indices[e]] * (vi - b.velocities[bn.indices[e]]).dot(bn.gradW[e]);
  return rate;
}

// Fluid part of the pressure acceleration, Eq. (9) written with beta = p / rho^2 (= lambda / rho,
// Eq. 24): -sum_j m_j (beta_i + beta_j) grad W_ij.
inline Vector3r fluidPressureAcceleration(const StepContext& ctx, std::size_t i, const std::vector<Real>& beta) {
  const FluidModel& f = ctx.fluid;
  const NeighborLists& fn = ctx.fluidNeighbors;
  const Real bi = beta[i];
  Vector3r a = Vector3r::Zero();
  for (Index e = fn.begin(i); e < fn.end(i); ++e) {
    const Index j = fn.indices[e];
    a -= f.masses[j] * (bi + beta[j]) * fn.gradW[e];
  }
  return a;
}

// sum_j m_j |grad W_ij|^2 m_i (Eq. 12) and the gradient sum sum_j m_j grad W_ij, for the diagonal.
inline void fluidDiagonalSums(const StepContext& ctx, std::size_t i, Vector3r& gradientSum, Real& squares) {
  const FluidModel& f = ctx.fluid;
  const NeighborLists& fn = ctx.fluidNeighbors;
  const Real mi = f.masses[i];
  for (Index e = fn.begin(i); e < fn.end(i); ++e) {
    const Real mj = f.masses[fn.indices[e]];
    gradientSum += mj * fn.gradW[e];
    squares += mi * mj * fn.gradW[e].squaredNorm();
  }
}

}  // namespace consph
