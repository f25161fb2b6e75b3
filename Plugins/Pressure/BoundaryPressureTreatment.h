// How boundary neighbours k of a fluid particle i enter an SPH pressure solve: the one place
// DFSPH, IISPH and WCSPH share, selected per scene by simulation.boundaryPressure.
//
//   consistent     J. Bender, L. Westhofen, S. R. Jeske: Consistent SPH Rigid-Fluid Coupling.
//                  VMV 2023, Eqs. (29)-(34): boundary gradients only inside the squared gradient
//                  sum of the diagonal (Eq. 32), no boundary pressure in a_i^p (Eq. 33).
//   mirroring      N. Akinci, M. Ihmsen, G. Akinci, B. Solenthaler, M. Teschner: Versatile
//                  rigid-fluid coupling for incompressible SPH. ACM TOG 31(4), 2012:
//                  p_k = p_i, a_k^p = 0 in Eqs. (15)-(17).
//   extrapolation  S. Band, C. Gissler, A. Peer, M. Teschner: MLS pressure boundaries for
//                  divergence-free and viscous SPH fluids. Computers & Graphics 76, 2018:
//                  p_k = max(0, linear MLS fit of the fluid pressures around x_k), a_k^p = 0,
//                  in Eqs. (15)-(17).
//
// Every treatment writes the boundary part of the pressure acceleration as
//   a_i^p,b = -sum_k m~_k (p_i / rho_i^2 + p_k / rho0^2) grad W_ik      (Eq. 16; Eq. 33: p_k = 0)
// Consistent and mirroring have p_k = 0 or p_i, so the sum collapses to a coefficient times the
// per-particle vector g_i = sum_k m~_k grad W_ik, computed once per step: the solvers' iterations
// then never visit boundary neighbours (nor for the density rate's boundary part, densityRate,
// while the samples keep their velocities through the solve). Extrapolation must visit them (p_k
// differs per k) and additionally fits p_k once per iteration; that is its intrinsic extra cost.
//
// Diagonal (documented choice): extrapolation uses the classical Eq. (15), like mirroring. The
// extrapolated p_k depends on p_i through the MLS fit, and near a wall p_k ~ p_i, so the row of
// p_i really contains a boundary term of the size of Eq. (15)'s sum_k m_i m~_k |grad W_ik|^2; the
// consistent diagonal (Eq. 32) would ignore it and over-relax the Jacobi iteration at walls.
//
// The solvers call the inline members below inside their parallel loops: no virtual call and no
// branch per neighbour (one switch per particle).
#pragma once
#include <algorithm>
#include <span>
#include <vector>

#include "Simulation/StepContext.h"
#include "Utilities/ParallelFor.h"

namespace consph {

class BoundaryPressureTreatment {
 public:
  // The treatment a solver is built with (the scene's simulation.boundaryPressure, "auto"
  // resolved: PluginContext::boundaryPressure); it holds for the whole run.
  explicit BoundaryPressureTreatment(BoundaryPressure mode = BoundaryPressure::Consistent)
      : mode_(mode), classicalDiagonal_(mode != BoundaryPressure::Consistent) {}

  // Once per step, after the neighbour search and the densities: the per-particle boundary
  // gradient sums g_i, the Eq. (15) diagonal terms (mirroring, extrapolation) and, for
  // extrapolation only, the boundary -> fluid lists and MLS coefficients (positions are fixed
  // during the solve, so the moment matrices are inverted once per step, not per iteration).
  void beginStep(const StepContext& ctx);

  BoundaryPressure mode() const { return mode_; }
  bool extrapolates() const { return mode_ == BoundaryPressure::Extrapolation; }

  // g_i = sum_k m~_k grad W_ik: enters the squared gradient sum of Eqs. (15) and (32).
  const Vector3r& boundaryGradient(std::size_t i) const { return gradientSum_[i]; }
  // Eq. (14)'s boundary part of the density rate, sum_k m~_k (v_i - v_k) . grad W_ik, as
  // v_i . g_i - sum_k m~_k v_k . grad W_ik: the second sum is taken in beginStep (0 where no
  // sample moves), so a solver's iterations visit no boundary neighbour for it either. Valid while
  // the samples keep the velocities they had at beginStep: a solver that moves them between its
  // iterations (BodyResponse) sums over the pairs instead (SphPressureTerms.h, boundaryDensityRate).
  // Only after keepSampleFlux(), which asks every beginStep for the second sum (a solver that
  // does not read the rate from here, WCSPH or IISPH, then pays no scan of the samples for it).
  void keepSampleFlux() { keepSampleFlux_ = true; }
  Real densityRate(std::size_t i, const Vector3r& vi) const {
    return vi.dot(gradientSum_[i]) - (sampleFlux_.empty() ? Real(0) : sampleFlux_[i]);
  }
  // Eq. (15)'s sum_k m_i m~_k |grad W_ik|^2 (mirroring, extrapolation). Consistent (Eq. 32):
  // that term times the particle's squeeze, 1 - |sum_o g_o| / sum_o |g_o| over the boundary
  // objects o it meets (g_o: g_i's part from object o): 0 against one object, where Eq. (32)
  // stands as it is; towards 1 in a gap that two objects close from opposite sides. There g_i
  // cancels, and with few fluid neighbours Eq. (32)'s diagonal all but vanishes although the
  // rows of the gap particle's neighbours still couple to it: the Jacobi step, s / D, then
  // overshoots by orders of magnitude (a box landing on a floor gave one particle 634 kPa at
  // 1.02 rho0 and 40 m/s, through the floor), and since the density sources count compression
  // only, an overshoot is never undone. The diagonal only scales the iteration's steps, so the
  // pressures it converges to are the same (docs/boundary-pressure.md, "Closing gaps").
  // Sampled walls only: with volume maps it stops the same blow-up, but a box landing on the
  // floor then hovers on the last fluid layers (0.01-0.03 m/s for 5 s), where without it the
  // box came down on its side; that hovering is volume maps' own open problem (issue 15).
  Real diagonalTerm(std::size_t i) const { return diagonalTerm_[i]; }
  // Asks every beginStep to keep each particle's squeeze (as above) for squeeze(i), also where
  // the diagonal does not weight by it (DFSPH's maxErrorParticle tells closing gaps by it).
  void keepSqueeze() { keepSqueeze_ = true; }
  // The squeeze of fluid particle i, after beginStep; only after keepSqueeze().
  Real squeeze(std::size_t i) const { return squeeze_[i]; }
  // Extrapolation: the diagonal's boundary term, Eq. (15)'s plus how p_k = sum_f c_kf p_f moves
  // with p_i, (rho_i^2 / rho0^2) h_i . S_i with h_i = sum_k m~_k c_ki grad W_ik and S_i the full
  // gradient sum (fluid and boundary), where positive. With MLS, c_ki can well exceed 1 next to a
  // wall (the fit extrapolates), and a relaxed Jacobi step sized by Eq. (15) alone overshoots
  // and diverges (IISPH dropping a cube into a sphere leaked through it). Erring large only
  // slows the iteration; measured on SphereDrop: 34.3 iterations per step either way, no
  // iteration-cap hit (taking the larger of the two terms instead of their sum left 4).
  // computeExtrapolationCoupling() fills h_i, after beginStep(); only a solver that uses this
  // term (IISPH) pays for it.
  void computeExtrapolationCoupling(const StepContext& ctx);
  Real extrapolationDiagonalTerm(std::size_t i, const Vector3r& gradientSum, Real rhoI) const {
    return diagonalTerm(i) + std::max(Real(0), rhoI * rhoI * invRho0Squared_ * extrapolationGradient_[i].dot(gradientSum));
  }

  // Boundary part of a_i^p for fluid pressure p_i (beta_i = p_i / rho_i^2); `pk` holds p_k per
  // boundary sample (read by extrapolation only: boundaryPressures() or boundaryPressureChanges()).
  Vector3r acceleration(const StepContext& ctx, std::size_t i, Real betaI, Real pI, const std::vector<Real>& pk) const {
    switch (mode_) {
      case BoundaryPressure::Consistent: return -betaI * gradientSum_[i];  // Eq. (33)
      case BoundaryPressure::Mirroring: return -(betaI + pI * invRho0Squared_) * gradientSum_[i];  // Eq. (16), p_k = p_i
      case BoundaryPressure::Extrapolation: break;
    }
    // Eq. (16) with the extrapolated p_k.
    const NeighborLists& bn = ctx.boundaryNeighbors;
    Vector3r a = -betaI * gradientSum_[i];
    for (Index e = bn.begin(i); e < bn.end(i); ++e) {
      const Index k = bn.indices[e];
      a -= (ctx.boundary.masses[k] * pk[k] * invRho0Squared_) * bn.gradW[e];
    }
    return a;
  }

  // The factor b_ik of the boundary term -m~_k b_ik grad W_ik of a_i^p (Eq. 33: beta_i; Eq. 16:
  // beta_i + p_k / rho0^2): what the reaction on boundary sample k, Eq. (35), multiplies.
  Real pairFactor(Index k, Real betaI, Real pI, const std::vector<Real>& pk) const {
    switch (mode_) {
      case BoundaryPressure::Consistent: return betaI;
      case BoundaryPressure::Mirroring: return betaI + pI * invRho0Squared_;
      case BoundaryPressure::Extrapolation: break;
    }
    return betaI + pk[k] * invRho0Squared_;
  }

  // The reaction on every boundary sample, Eq. (35), of one application of the boundary term
  // over `dt` with pressures beta_i = p_i / rho_i^2 and p_i (explicit solvers, or an implicit
  // one that applies its final pressures once): dt m_i m~_k b_ik grad W_ik per pair.
  void reactionImpulses(const StepContext& ctx, Real dt, const std::vector<Real>& beta, std::span<const Real> pressure,
                        std::vector<Vector3r>& impulsePerPair) const;

  // Extrapolation: p_k = max(0, sum_f c_kf p_f) from the fluid pressures pressureOf(f); keeps the
  // change against the previous call in boundaryPressureChanges() (DFSPH applies increments).
  template <class PressureOf>
  void extrapolate(PressureOf&& pressureOf) {
    const NeighborLists& t = boundaryToFluid_;
    const std::size_t nk = pk_.size();
    parallelFor(nk, [&](std::size_t k) {
      Real p = 0;
      for (Index e = t.begin(k); e < t.end(k); ++e) p += mlsCoefficients_[e] * pressureOf(t.indices[e]);
      p = std::max(p, Real(0));
      pkChange_[k] = p - pk_[k];
      pk_[k] = p;
    });
  }
  // Sets p_k = 0 (the start of a solve that applies its pressure as increments).
  void resetBoundaryPressures();
  const std::vector<Real>& boundaryPressures() const { return pk_; }
  const std::vector<Real>& boundaryPressureChanges() const { return pkChange_; }
  // Boundary samples whose moment matrix was near-singular this step (weighted-average fallback).
  std::size_t fallbackCount() const { return fallbacks_; }
  // Boundary samples whose slope was scaled down to kMaxSlopeAmplification this step.
  std::size_t limitedSlopeCount() const { return limitedSlopes_; }

  // Smallest / largest eigenvalue of the weighted moment matrix below which it counts as
  // near-singular: the fluid around x_k is (nearly) a plane or a line and cannot give a slope
  // along the missing direction, which is exactly the direction towards the wall.
  static constexpr Real kSingularRatio = Real(1e-2);
  // The largest amplification max_f |(x_f - x_bar) . M^-1 (x_k - x_bar)| of the fitted slope; a
  // steeper fit is scaled down to it (p_k stays linear in the fluid pressures, so the solvers'
  // diagonals hold). Two lattice layers over a flat wall (the test ExtrapolationReproduces-
  // ALinearPressureField) need 21: the layer at 3r sits in the kernel's tail, so the fluid's
  // weighted spread along the normal is small. The few particles left in a tank's corner as a
  // dam break drains gave hundreds (not singular at kSingularRatio), and single particles were
  // thrown out: +7.5 % of the energy in one step at r = 0.02, dt = 0.5 ms, 12.8 m/s at r = 0.01.
  // Measured 2026-12-02 (bench/RESULTS.md, "Density drift and the time step"): 30 stops those and
  // keeps the resting tank within its bounds; 50 let 0.7 % steps through.
  static constexpr Real kMaxSlopeAmplification = Real(30);

 private:
  void computeMlsCoefficients(const StepContext& ctx);
  // The squeeze of fluid particle i with boundary gradient sum g (diagonalTerm), in [0, 1].
  Real squeezeOf(const StepContext& ctx, std::size_t i, const Vector3r& g) const;

  BoundaryPressure mode_ = BoundaryPressure::Consistent;
  std::vector<Vector3r> extrapolationGradient_;  // h_i, extrapolation only
  bool classicalDiagonal_ = false;
  // Most boundary objects one particle's squeeze tells apart; more fold into the last.
  static constexpr int kSqueezeObjects = 4;
  Real invRho0Squared_ = 0;
  std::vector<Vector3r> gradientSum_;  // (n fluid) g_i = sum_k m~_k grad W_ik
  bool keepSampleFlux_ = false;
  std::vector<Real> sampleFlux_;       // (n fluid) sum_k m~_k v_k . grad W_ik; empty where no sample moves or not kept
  std::vector<Real> diagonalTerm_;     // (n fluid) sum_k m_i m~_k |grad W_ik|^2 (consistent: times the squeeze)
  bool keepSqueeze_ = false;
  std::vector<Real> squeeze_;          // (n fluid) the squeeze, with keepSqueeze() only
  NeighborLists boundaryToFluid_;      // boundary k -> fluid f (extrapolation only)
  std::vector<Real> mlsCoefficients_;  // (pairs of boundaryToFluid_) c_kf
  std::vector<Real> pk_, pkChange_;    // (n boundary) p_k and its last change, Pa
  std::size_t fallbacks_ = 0;
  std::size_t limitedSlopes_ = 0;
};

}  // namespace consph
