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
#include "Simulation/StepContext.h"

namespace consph::viscosity {

inline constexpr Real kLaplacianFactor = 10;  // 2 (d + 2), d = 3

// Regularisation 0.01 h^2 of the denominator (avoids the singularity at x_ij = 0).
inline Real regularisation(const CubicSplineKernel& kernel) {
  return Real(0.01) * kernel.supportRadius() * kernel.supportRadius();
}

// sum_j (m_j / rho_j) (u_ij . x_ij) / (|x_ij|^2 + eps) grad W_ij for any particle vector field u.
inline Vector3r fluidSum(const FluidView& f, const NeighborLists& fn, std::size_t i, const Vector3r* u, Real eps) {
  const Vector3r xi = f.positions[i], ui = u[i];
  Vector3r s = Vector3r::Zero();
  for (Index e = fn.begin(i); e < fn.end(i); ++e) {
    const Index j = fn.indices[e];
    const Vector3r xij = xi - f.positions[j];
    s += (f.masses[j] / f.densities[j]) * ((ui - u[j]).dot(xij) / (xij.squaredNorm() + eps)) * fn.gradient(e, xij);
  }
  return s;
}

// fluidSum for the velocities, and in the same pass the upper triangle (xx, yy, zz, xy, xz, yz)
// of its rate matrix sum_j (m_j / rho_j) |x_ij . grad W_ij| / ((|x_ij|^2 + eps) |x_ij|^2) x_ij x_ij^T:
// how fast the sum changes with v_i (Viscosity_Standard's step bound), at six multiply-adds per
// neighbour and no second visit.
inline Vector3r fluidSumWithRate(const FluidView& f, const NeighborLists& fn, std::size_t i, Real eps, Real (&rate)[6]) {
  const Vector3r xi = f.positions[i], vi = f.velocities[i];
  Vector3r s = Vector3r::Zero();
  // Local accumulators: the compiler cannot keep `rate` in registers (it could alias the fields).
  Vector3r diagonal = Vector3r::Zero(), offDiagonal = Vector3r::Zero();  // (xx, yy, zz), (xy, xz, yz)
  for (Index e = fn.begin(i); e < fn.end(i); ++e) {
    const Index j = fn.indices[e];
    const Vector3r xij = xi - f.positions[j];
    const Real weight = (f.masses[j] / f.densities[j]) / (xij.squaredNorm() + eps);
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
