// The SPH velocity Laplacian shared by the explicit (Viscosity_Standard) and the implicit
// (Viscosity_Weiler2018) viscosity, in the momentum-conserving form of
//   J. P. Morris, P. J. Fox, Y. Zhu: Modeling low Reynolds number incompressible flows using SPH.
//   Journal of Computational Physics 136(1), 1997, 214-226,
// as Weiler et al. 2018 (Eq. 7) write it with the dynamic viscosity mu = rho0 nu:
//   a_i = 2 (d + 2) nu (rho0 / rho_i) sum_j (m_j / rho_j) (v_ij . x_ij) / (|x_ij|^2 + 0.01 h^2) grad W_ij
//       + 2 (d + 2) nu_b sum_k (m~_k / rho_i) ((v_i - v_k) . x_ik) / (|x_ik|^2 + 0.01 h^2) grad W_ik.
// Why this form: the pair weight m_i m_j / (rho_i rho_j) is symmetric and grad W_ij is parallel to
// x_ij, so every pair's forces are equal, opposite and central: linear and angular momentum are
// conserved exactly, and a rigid motion (v_ij . x_ij = 0) feels none. SPlisHSPlasH's Standard
// viscosity weights by m_j / rho_j alone, which equals this at rho_i = rho0 but is not symmetric
// at a free surface. The boundary term is the same with rho_k = rho0 (boundary mass m~_k = rho0 V_k).
#pragma once
#include <vector>

#include "Simulation/StepContext.h"
#include "Utilities/ParallelFor.h"
#include "Utilities/SimdLanes.h"

namespace consph::viscosity {

inline constexpr Real kLaplacianFactor = 10;  // 2 (d + 2), d = 3

// Regularisation 0.01 h^2 of the denominator (avoids the singularity at x_ij = 0).
inline Real regularisation(const CubicSplineKernel& kernel) {
  return Real(0.01) * kernel.supportRadius() * kernel.supportRadius();
}

// V_j = m_j / rho_j of every fluid particle, for the one-pair-at-a-time sums below: once per
// particle instead of once per pair, same bits. A division per pair less was worth 3-6 % of the
// loop on Zen 3 (bench/pair_loops.cpp): it was not what bound it.
inline void fluidVolumes(const FluidView& f, std::vector<Real>& volumes) {
  volumes.resize(f.size());
  parallelFor(f.size(), [&](std::size_t j) { volumes[j] = f.masses[j] / f.densities[j]; });
}

// sum_j V_j (u_ij . x_ij) / (|x_ij|^2 + eps) grad W_ij for any particle vector field u, with the
// volumes V_j = m_j / rho_j of fluidVolumes: the reference of packedFluidSum below, which
// Viscosity_Weiler2018 runs (tests/unit/test_packed_pair_sums.cpp).
inline Vector3r fluidSum(const FluidView& f, const NeighborLists& fn, std::size_t i, const Vector3r* u, const Real* volumes, Real eps) {
  const Vector3r xi = f.positions[i], ui = u[i];
  Vector3r s = Vector3r::Zero();
  for (Index e = fn.begin(i); e < fn.end(i); ++e) {
    const Index j = fn.indices[e];
    const Vector3r xij = xi - f.positions[j];
    s += volumes[j] * ((ui - u[j]).dot(xij) / (xij.squaredNorm() + eps)) * fn.gradient(e, xij);
  }
  return s;
}

// fluidSum a block of pairs at a time, over the padded rows of Simulation/PaddedNeighborLists.h,
// the slots (x, y, z, V) in `positionsVolumes` and the slots (u, 0) of the field u in `field`:
// Weiler 2018's operator, applied in every iteration of its solve.
inline Vector3r packedFluidSum(const PaddedNeighborLists& fn, std::size_t i, const Real* positionsVolumes, const Real* field, Real eps) {
  const Real* xs = positionsVolumes;
  const Real* us = field;
  const Index end = fn.end(i);
#if defined(CONSPH_SIMD_AVX2)
  using L = simd::Lanes<Real>;
  using V = L::V;
  const V xi = L::set1(xs[4 * i]), yi = L::set1(xs[4 * i + 1]), zi = L::set1(xs[4 * i + 2]);
  const V uxi = L::set1(us[4 * i]), uyi = L::set1(us[4 * i + 1]), uzi = L::set1(us[4 * i + 2]), epsilon = L::set1(eps);
  V sx = L::zero(), sy = L::zero(), sz = L::zero();
  for (Index e = fn.begin(i); e < end; e += kPairBlock) {
    V x, y, z, volume, ux, uy, uz, unused;
    L::transpose(xs, &fn.indices[e], x, y, z, volume);
    L::transpose(us, &fn.indices[e], ux, uy, uz, unused);
    const V dx = L::sub(xi, x), dy = L::sub(yi, y), dz = L::sub(zi, z);
    const V r2 = L::fmadd(dz, dz, L::fmadd(dy, dy, L::mul(dx, dx)));
    const V dot = L::fmadd(dz, L::sub(uzi, uz), L::fmadd(dy, L::sub(uyi, uy), L::mul(dx, L::sub(uxi, ux))));
    const V c = L::mul(L::mul(volume, L::div(dot, L::add(r2, epsilon))), L::load(&fn.gradFactors[e]));
    sx = L::fmadd(c, dx, sx), sy = L::fmadd(c, dy, sy), sz = L::fmadd(c, dz, sz);
  }
  return Vector3r(L::sum(sx), L::sum(sy), L::sum(sz));
#else
  Vector3r s = Vector3r::Zero();
  for (Index e = fn.begin(i); e < end; ++e) {
    const std::size_t j = 4 * std::size_t(fn.indices[e]);
    const Vector3r xij(xs[4 * i] - xs[j], xs[4 * i + 1] - xs[j + 1], xs[4 * i + 2] - xs[j + 2]);
    const Vector3r uij(us[4 * i] - us[j], us[4 * i + 1] - us[j + 1], us[4 * i + 2] - us[j + 2]);
    s += (xs[j + 3] * (uij.dot(xij) / (xij.squaredNorm() + eps)) * fn.gradFactors[e]) * xij;
  }
  return s;
#endif
}

// fluidSum for the velocities, and in the same pass the upper triangle (xx, yy, zz, xy, xz, yz)
// of its rate matrix sum_j (m_j / rho_j) |x_ij . grad W_ij| / ((|x_ij|^2 + eps) |x_ij|^2) x_ij x_ij^T:
// how fast the sum changes with v_i (Viscosity_Standard's step bound), at six multiply-adds per
// neighbour and no second visit. Viscosity_Standard runs packedFluidSumWithRate below; this
// one-pair-at-a-time form is its reference (tests/unit/test_packed_pair_sums.cpp).
inline Vector3r fluidSumWithRate(const FluidView& f, const NeighborLists& fn, std::size_t i, const Real* volumes, Real eps,
                                 Real (&rate)[6]) {
  const Vector3r xi = f.positions[i], vi = f.velocities[i];
  Vector3r s = Vector3r::Zero();
  // Local accumulators: the compiler cannot keep `rate` in registers (it could alias the fields).
  Vector3r diagonal = Vector3r::Zero(), offDiagonal = Vector3r::Zero();  // (xx, yy, zz), (xy, xz, yz)
  for (Index e = fn.begin(i); e < fn.end(i); ++e) {
    const Index j = fn.indices[e];
    const Vector3r xij = xi - f.positions[j];
    const Real weight = volumes[j] / (xij.squaredNorm() + eps);
    const Vector3r gradW = fn.gradient(e, xij);
    s += (weight * (vi - f.velocities[j]).dot(xij)) * gradW;
    // grad W_ij = W'(r) x_ij / r is parallel to x_ij, so |x . grad W| x x^T / |x|^2 = -x grad W^T.
    const Vector3r g = -weight * gradW;
    diagonal += xij.cwiseProduct(g);
    offDiagonal += Vector3r(xij[0], xij[0], xij[1]).cwiseProduct(Vector3r(g[1], g[2], g[2]));
  }
  for (int c = 0; c < 3; ++c) rate[c] += diagonal[c], rate[3 + c] += offDiagonal[c];
  return s;
}

// fluidSumWithRate a block of pairs at a time (Utilities/SimdLanes.h), over the padded rows of
// Simulation/PaddedNeighborLists.h and the slots (x, y, z, V) in `positionsVolumes` and (vx, vy,
// vz, 0) in `velocities`: 4.1 -> 1.8 ns per listed pair on one thread, Zen 3, float, packing
// included (bench/pair_loops.cpp). The same sums in another order (last bits differ).
inline Vector3r packedFluidSumWithRate(const PaddedNeighborLists& fn, std::size_t i, const Real* positionsVolumes,
                                       const Real* velocities, Real eps, Real (&rate)[6]) {
  const Real* xs = positionsVolumes;
  const Real* vs = velocities;
  const Index end = fn.end(i);
#if defined(CONSPH_SIMD_AVX2)
  using L = simd::Lanes<Real>;
  using V = L::V;
  const V xi = L::set1(xs[4 * i]), yi = L::set1(xs[4 * i + 1]), zi = L::set1(xs[4 * i + 2]);
  const V vxi = L::set1(vs[4 * i]), vyi = L::set1(vs[4 * i + 1]), vzi = L::set1(vs[4 * i + 2]), epsilon = L::set1(eps);
  V sx = L::zero(), sy = L::zero(), sz = L::zero();
  V xx = L::zero(), yy = L::zero(), zz = L::zero(), xy = L::zero(), xz = L::zero(), yz = L::zero();
  for (Index e = fn.begin(i); e < end; e += kPairBlock) {
    V x, y, z, volume, vx, vy, vz, unused;
    L::transpose(xs, &fn.indices[e], x, y, z, volume);
    L::transpose(vs, &fn.indices[e], vx, vy, vz, unused);
    const V dx = L::sub(xi, x), dy = L::sub(yi, y), dz = L::sub(zi, z);
    const V weight = L::div(volume, L::add(L::fmadd(dz, dz, L::fmadd(dy, dy, L::mul(dx, dx))), epsilon));
    const V factor = L::load(&fn.gradFactors[e]);
    const V dot = L::fmadd(dz, L::sub(vzi, vz), L::fmadd(dy, L::sub(vyi, vy), L::mul(dx, L::sub(vxi, vx))));
    const V c = L::mul(L::mul(weight, dot), factor);  // s += weight (v_ij . x_ij) W'/r x_ij
    sx = L::fmadd(c, dx, sx), sy = L::fmadd(c, dy, sy), sz = L::fmadd(c, dz, sz);
    // g = -weight grad W = -(weight W'/r) x_ij; the rate adds x_ij g^T's upper triangle.
    const V wf = L::mul(weight, factor);
    const V gx = L::mul(wf, dx), gy = L::mul(wf, dy), gz = L::mul(wf, dz);
    xx = L::fnmadd(dx, gx, xx), yy = L::fnmadd(dy, gy, yy), zz = L::fnmadd(dz, gz, zz);
    xy = L::fnmadd(dx, gy, xy), xz = L::fnmadd(dx, gz, xz), yz = L::fnmadd(dy, gz, yz);
  }
  rate[0] += L::sum(xx), rate[1] += L::sum(yy), rate[2] += L::sum(zz);
  rate[3] += L::sum(xy), rate[4] += L::sum(xz), rate[5] += L::sum(yz);
  return Vector3r(L::sum(sx), L::sum(sy), L::sum(sz));
#else
  Vector3r s = Vector3r::Zero();
  for (Index e = fn.begin(i); e < end; ++e) {
    const std::size_t j = 4 * std::size_t(fn.indices[e]);
    const Vector3r xij(xs[4 * i] - xs[j], xs[4 * i + 1] - xs[j + 1], xs[4 * i + 2] - xs[j + 2]);
    const Vector3r vij(vs[4 * i] - vs[j], vs[4 * i + 1] - vs[j + 1], vs[4 * i + 2] - vs[j + 2]);
    const Real weight = xs[j + 3] / (xij.squaredNorm() + eps);
    s += (weight * vij.dot(xij) * fn.gradFactors[e]) * xij;
    const Vector3r g = -(weight * fn.gradFactors[e]) * xij;
    rate[0] += xij[0] * g[0], rate[1] += xij[1] * g[1], rate[2] += xij[2] * g[2];
    rate[3] += xij[0] * g[1], rate[4] += xij[0] * g[2], rate[5] += xij[1] * g[2];
  }
  return s;
#endif
}

// sum_k m~_k ((ui - w_k) . x_ik) / (|x_ik|^2 + eps) grad W_ik, with w_k the boundary velocity
// (withBoundaryVelocity) or zero (the part of the term that is linear in ui).
inline Vector3r boundarySum(const BoundaryView& b, const NeighborLists& bn, std::size_t i, const Vector3r& xi, const Vector3r& ui,
                            Real eps, bool withBoundaryVelocity) {
  Vector3r s = Vector3r::Zero();
  for (Index e = bn.begin(i); e < bn.end(i); ++e) {
    const Index k = bn.indices[e];
    const Vector3r xik = xi - b.positions[k];
    const Vector3r uik = withBoundaryVelocity ? Vector3r(ui - b.velocities[k]) : ui;
    s += b.masses[k] * (uik.dot(xik) / (xik.squaredNorm() + eps)) * bn.gradW[e];
  }
  return s;
}

}  // namespace consph::viscosity
