// The two fluid sums DFSPH runs in every iteration, a block of pairs at a time:
//   the density rate   sum_j m_j (v_i - v_j) . grad W_ij                 (Eq. 6's fluid part)
//   the pressure term  -sum_j m_j (beta_i + beta_j) grad W_ij            (Eq. 9 / 24)
// with grad W_ij = x_ij gradFactor_ij, over the padded rows of Simulation/PaddedNeighborLists.h and
// the slots (x, y, z, m_j beta_j) and (vx, vy, vz, m) of PackedParticles, in the lanes of
// Utilities/SimdLanes.h (a plain loop over the same rows and slots without AVX2).
// Why a second form of SphPressureTerms.h's loops: those load j's position, velocity and mass from
// three arrays of 12-byte vectors and spend about 5-6 cycles per pair on it; factoring the
// arithmetic or breaking the sum's dependency chain gained under 10 %. Measured on one thread
// (bench/pair_loops.cpp; bench/RESULTS.md, "Packed pair sums"): density rate 1.9 -> 1.4 ns per
// listed pair, pressure term 1.6 -> 1.3, packing and padding included.
// The lanes sum in another order than the scalar loops, so the results differ from
// SphPressureTerms.h's in the last bits (tests/unit/test_packed_pair_sums.cpp); every order is
// deterministic and independent of the thread count.
#pragma once
#include <cstddef>
#include <vector>

#include "Simulation/PaddedNeighborLists.h"
#include "Simulation/ParticleView.h"
#include "Utilities/SimdLanes.h"

namespace consph {

// The slots the packed sums read, in the fluid's order.
struct PackedParticles {
  std::vector<Real> positions;   // x, y, z, m_j beta_j of the pressures being applied (packPressures)
  std::vector<Real> velocities;  // vx, vy, vz, m

  // Positions: once per step (they stay fixed through the solves).
  void packPositions(const FluidView& f) {
    packSlots(positions, f.size(), [&](std::size_t i, Real* s) {
      s[0] = f.positions[i][0], s[1] = f.positions[i][1], s[2] = f.positions[i][2], s[3] = 0;
    });
  }
  // m_j beta_j: before every pressure pass (a gather of beta_j in the loop, instead, waited
  // ~20 cycles per block: a quarter of the pass's samples sat behind it).
  void packPressures(const FluidView& f, const Real* beta) {
    parallelFor(f.size(), [&](std::size_t i) { positions[4 * i + 3] = f.masses[i] * beta[i]; });
  }
  // Velocities and masses: before a density-rate pass, unless every slot was written since the
  // velocities last changed (setVelocity, from the loop that changes them).
  void packVelocities(const FluidView& f) {
    packSlots(velocities, f.size(), [&](std::size_t i, Real* s) { setVelocity(s, f, i); });
  }
  static void setVelocity(Real* s, const FluidView& f, std::size_t i) {
    s[0] = f.velocities[i][0], s[1] = f.velocities[i][1], s[2] = f.velocities[i][2], s[3] = f.masses[i];
  }
};

// sum_j m_j (v_i - v_j) . grad W_ij over i's fluid neighbours (packVelocities first).
inline Real packedFluidDensityRate(const PaddedNeighborLists& fn, std::size_t i, const PackedParticles& p) {
  const Real* xs = p.positions.data();
  const Real* vs = p.velocities.data();
  const Index end = fn.end(i);
#if defined(CONSPH_SIMD_AVX2)
  using L = simd::Lanes<Real>;
  using V = L::V;
  const V xi = L::set1(xs[4 * i]), yi = L::set1(xs[4 * i + 1]), zi = L::set1(xs[4 * i + 2]);
  const V vxi = L::set1(vs[4 * i]), vyi = L::set1(vs[4 * i + 1]), vzi = L::set1(vs[4 * i + 2]);
  V rate = L::zero();
  for (Index e = fn.begin(i); e < end; e += kPairBlock) {
    V x, y, z, unused, vx, vy, vz, m;
    L::transpose(xs, &fn.indices[e], x, y, z, unused);
    L::transpose(vs, &fn.indices[e], vx, vy, vz, m);
    V dot = L::mul(L::sub(xi, x), L::sub(vxi, vx));
    dot = L::fmadd(L::sub(yi, y), L::sub(vyi, vy), dot);
    dot = L::fmadd(L::sub(zi, z), L::sub(vzi, vz), dot);
    rate = L::fmadd(L::mul(m, L::load(&fn.gradFactors[e])), dot, rate);
  }
  return L::sum(rate);
#else
  Real rate = 0;
  for (Index e = fn.begin(i); e < end; ++e) {
    const std::size_t j = 4 * std::size_t(fn.indices[e]);
    Real dot = 0;
    for (int c = 0; c < 3; ++c) dot += (xs[4 * i + c] - xs[j + c]) * (vs[4 * i + c] - vs[j + c]);
    rate += vs[j + 3] * fn.gradFactors[e] * dot;
  }
  return rate;
#endif
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
