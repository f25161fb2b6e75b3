// The two fluid sums DFSPH runs in every iteration, a block of pairs at a time:
//   the density rate   sum_j m_j (v_i - v_j) . grad W_ij                 (Eq. 6's fluid part)
//   the pressure term  -sum_j m_j (beta_i + beta_j) grad W_ij            (Eq. 9 / 24)
// with grad W_ij = x_ij gradFactor_ij, over the padded rows of Simulation/PaddedNeighborLists.h and
// the slots (x, y, z, m_j beta_j) and (m v_x, m v_y, m v_z, m (x - o) . v) of PackedParticles, in
// the lanes of Utilities/SimdLanes.h (a plain loop over the same rows and slots without AVX2).
// Why a second form of SphPressureTerms.h's loops: those load j's position, velocity and mass from
// three arrays of 12-byte vectors and spend about 5-6 cycles per pair on it; factoring the
// arithmetic or breaking the sum's dependency chain gained under 10 %. Measured on one thread
// (bench/pair_loops.cpp; bench/RESULTS.md, "Packed pair sums"): density rate 1.9 -> 1.4 ns per
// listed pair, pressure term 1.6 -> 1.3, packing and padding included; the density rate from one
// slot per pair (below) 1.43 -> 0.82 (bench/RESULTS.md, "... the density rate from one slot per pair").
// The lanes sum in another order than the scalar loops, so the results differ from
// SphPressureTerms.h's in the last bits (tests/unit/test_packed_pair_sums.cpp); every order is
// deterministic and independent of the thread count.
#pragma once
#include <cstddef>
#include <vector>

#include "Simulation/PaddedNeighborLists.h"
#include "Simulation/ParticleView.h"
#include "Utilities/AxisAlignedBox.h"
#include "Utilities/SimdLanes.h"

namespace consph {

// The slots the packed sums read, in the fluid's order.
struct PackedParticles {
  std::vector<Real> positions;  // x, y, z, m_j beta_j of the pressures being applied (packPressures)
  std::vector<Real> momenta;    // m v_x, m v_y, m v_z, m (x - origin) . v
  // The centre of the fluid's bounding box when the positions were packed: the density rate's
  // one-slot form (packedFluidDensityRate) takes positions relative to it, which keeps its
  // round-off that of the fluid's extent over h rather than of the distance to the scene's origin.
  Vector3r origin = Vector3r::Zero();

  // Positions and the origin: once per step (they stay fixed through the solves).
  void packPositions(const FluidView& f) {
    packSlots(positions, f.size(), [&](std::size_t i, Real* s) {
      s[0] = f.positions[i][0], s[1] = f.positions[i][1], s[2] = f.positions[i][2], s[3] = 0;
    });
    if (f.size() == 0) return;
    const PointBox box = boxOfPoints(f.positions.data(), f.size());
    origin = Real(0.5) * (box.lo + box.hi);
  }
  // m_j beta_j: before every pressure pass (a gather of beta_j in the loop, instead, waited
  // ~20 cycles per block: a quarter of the pass's samples sat behind it).
  void packPressures(const FluidView& f, const Real* beta) {
    parallelFor(f.size(), [&](std::size_t i) { positions[4 * i + 3] = f.masses[i] * beta[i]; });
  }
  // Momenta: before a density-rate pass, unless every slot was written since the velocities last
  // changed (setMomentum, from the loop that changes them). packPositions first (the origin).
  void packMomenta(const FluidView& f) {
    packSlots(momenta, f.size(), [&](std::size_t i, Real* s) { setMomentum(s, f, i); });
  }
  void setMomentum(Real* s, const FluidView& f, std::size_t i) const {
    const Vector3r mv = f.masses[i] * f.velocities[i];
    s[0] = mv[0], s[1] = mv[1], s[2] = mv[2], s[3] = (f.positions[i] - origin).dot(mv);
  }
};

// sum_j m_j (v_i - v_j) . grad W_ij over i's fluid neighbours (packMomenta first), given
// G_i = sum_j m_j grad W_ij (massGradientSum). With x_ij = x_i - x_j and grad W_ij = x_ij f_ij,
//   sum_j m_j f_ij x_ij . (v_i - v_j) = v_i . G_i - (x_i - o) . sum_j f_ij m_j v_j + sum_j f_ij m_j (x_j - o) . v_j,
// so a pair reads one slot, (m_j v_j, m_j (x_j - o) . v_j), instead of two (x_j and v_j): 1.43 ->
// 0.82 ns per pair on one thread (bench/pair_loops.cpp). The price is round-off: the two sums are
// of size |x - o| |v| where the pair form's terms are of size |x_ij| |v_ij|, so the difference
// carries about (extent / h) (|v| / |v_ij|) units of round-off of the terms (float, measured: at
// most 0.06 kg/m^3/s in a heavy box's landing through water, 1.2e-7 rho0 over its 2 ms step,
// against the density solve's tolerance of 1e-4 rho0; tests/unit/test_packed_pair_sums.cpp bounds
// it on every particle; bench/RESULTS.md, "... the density rate from one slot per pair").
inline Real packedFluidDensityRate(const PaddedNeighborLists& fn, std::size_t i, const PackedParticles& p, const FluidView& f,
                                   const Vector3r& massGradientSum) {
  const Real* ms = p.momenta.data();
  const Index end = fn.end(i);
  Vector3r momentumSum;
  Real flux;
#if defined(CONSPH_SIMD_AVX2)
  using L = simd::Lanes<Real>;
  using V = L::V;
  V ax = L::zero(), ay = L::zero(), az = L::zero(), aw = L::zero();
  for (Index e = fn.begin(i); e < end; e += kPairBlock) {
    V mvx, mvy, mvz, mxv;
    L::transpose(ms, &fn.indices[e], mvx, mvy, mvz, mxv);
    const V factor = L::load(&fn.gradFactors[e]);
    ax = L::fmadd(factor, mvx, ax);
    ay = L::fmadd(factor, mvy, ay);
    az = L::fmadd(factor, mvz, az);
    aw = L::fmadd(factor, mxv, aw);
  }
  momentumSum = Vector3r(L::sum(ax), L::sum(ay), L::sum(az));
  flux = L::sum(aw);
#else
  momentumSum = Vector3r::Zero();
  flux = 0;
  for (Index e = fn.begin(i); e < end; ++e) {
    const Real* s = ms + 4 * std::size_t(fn.indices[e]);
    momentumSum += fn.gradFactors[e] * Vector3r(s[0], s[1], s[2]);
    flux += fn.gradFactors[e] * s[3];
  }
#endif
  return f.velocities[i].dot(massGradientSum) - (f.positions[i] - p.origin).dot(momentumSum) + flux;
}

// -sum_j m_j (beta_i + beta_j) grad W_ij over i's fluid neighbours, written as
// -(beta_i G_i + sum_j (m_j beta_j) grad W_ij) with G_i = sum_j m_j grad W_ij, which stays fixed
// through the solves (DFSPH keeps it from the diagonal's sums); packPressures(beta) first.
inline Vector3r packedFluidPressureAcceleration(const PaddedNeighborLists& fn, std::size_t i, const PackedParticles& p, Real betaI,
                                                const Vector3r& massGradientSum) {
  const Real* xs = p.positions.data();
  const Index end = fn.end(i);
#if defined(CONSPH_SIMD_AVX2)
  using L = simd::Lanes<Real>;
  using V = L::V;
  const V xi = L::set1(xs[4 * i]), yi = L::set1(xs[4 * i + 1]), zi = L::set1(xs[4 * i + 2]);
  V ax = L::zero(), ay = L::zero(), az = L::zero();
  for (Index e = fn.begin(i); e < end; e += kPairBlock) {
    V x, y, z, massPressure;
    L::transpose(xs, &fn.indices[e], x, y, z, massPressure);
    const V s = L::mul(massPressure, L::load(&fn.gradFactors[e]));
    ax = L::fnmadd(s, L::sub(xi, x), ax);
    ay = L::fnmadd(s, L::sub(yi, y), ay);
    az = L::fnmadd(s, L::sub(zi, z), az);
  }
  return Vector3r(L::sum(ax), L::sum(ay), L::sum(az)) - betaI * massGradientSum;
#else
  Vector3r a = Vector3r::Zero();
  for (Index e = fn.begin(i); e < end; ++e) {
    const std::size_t j = 4 * std::size_t(fn.indices[e]);
    const Real s = xs[j + 3] * fn.gradFactors[e];
    for (int c = 0; c < 3; ++c) a[c] -= s * (xs[4 * i + c] - xs[j + c]);
  }
  return a - betaI * massGradientSum;
#endif
}

}  // namespace consph
