#include "Plugins/Viscosity/Viscosity_Standard.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>

#include "Plugins/Viscosity/ViscosityLaplacian.h"
#include "Simulation/ParamBinding.h"
#include "Simulation/PluginRegistry.h"
#include "Utilities/ParallelFor.h"

namespace consph {

namespace {
const PluginRegistration<NonPressureForce> registration{
    "StandardViscosity", "explicit SPH-Laplacian viscosity (Morris et al. 1997), kinematic viscosity in m^2/s",
    Viscosity_Standard::parameters(), [](const Params& p, const PluginContext&) -> std::unique_ptr<NonPressureForce> {
      return std::make_unique<Viscosity_Standard>(p);
    }};
}  // namespace

const BoundParams<Viscosity_Standard>& Viscosity_Standard::bound() {
  static const BoundParams<Viscosity_Standard> table{
      bind({"viscosity", ParamType::Real, 0.01, "kinematic viscosity nu of the fluid, m^2/s", 0, 1e6},
           &Viscosity_Standard::viscosity_),
      bind({"boundaryViscosity", ParamType::Real, 0.0, "kinematic viscosity towards boundaries, m^2/s (0: free slip)", 0, 1e6},
           &Viscosity_Standard::boundaryViscosity_),
  };
  return table;
}

std::vector<ParamSpec> Viscosity_Standard::parameters() { return bound().specs(); }

Viscosity_Standard::Viscosity_Standard(const Params& p) { bound().assign(p, *this); }

Real Viscosity_Standard::maxStableTimeStep(const CubicSplineKernel& kernel) const {
  // Morris, Fox, Zhu 1997, Section 2.3: dt <= 0.125 h^2 / nu for the explicit viscous term, h
  // the smoothing length (their kernel's support is a multiple of h; the cubic spline's is 2h).
  // The boundary term is explicit as well: the larger of the two viscosities sets it.
  const Real nu = std::max(viscosity_, boundaryViscosity_);
  if (nu <= 0) return std::numeric_limits<Real>::infinity();
  const Real h = kernel.supportRadius() / 2;
  return Real(0.125) * h * h / nu;
}

void Viscosity_Standard::addAccelerations(StepContext& ctx) {
  using namespace viscosity;
  const FluidView& f = ctx.fluid;
  const Real eps = regularisation(ctx.kernel), rho0 = f.density0();
  const bool boundary = boundaryViscosity_ > 0;
  // The local stability bound (stepLimit). Written per pair, a_i = -sum_j c_ij P_ij (v_i - v_j)
  // with P_ij = x^_ij x^_ij^T and c_ij = 10 nu (rho0 / rho_i) (m_j / rho_j) |x_ij . grad W_ij|
  // / (|x_ij|^2 + eps) >= 0 (grad W_ij points along -x_ij), plus the boundary's c_ik P_ik v_i.
  // Explicit Euler on v' = -L v is stable for dt lambda_max(L) <= 2. A velocity that alternates
  // against its neighbours (the fastest mode: on a lattice it is L's largest eigenvalue) is
  // damped at the rate lambda_i = lambda_max(2 F_i + B_i), F_i = sum_j c_ij P_ij and
  // B_i = sum_k c_ik P_ik; so dt <= 2 / max_i lambda_i. In the bulk this is 3 / sum_j c_ij,
  // 0.90 ms at r = 0.004, nu = 0.01 (Morris' 0.125 h^2 / nu: 0.80 ms); a free surface's particles
  // have fewer neighbours but rho0 / rho_i and m_j / rho_j up to 2-3 times larger, and a 1 m
  // column's top corner at r = 0.004 oscillated step against step at 0.72 ms until it left at
  // 8 m/s (issue 15; docs/forces.md, "Stability").
  // lambda_max of the symmetric positive semi-definite 3 x 3 matrix, exactly (Eigen's closed
  // form), but only where its largest absolute row sum (Gershgorin, an upper bound: exact where
  // the neighbours surround the particle, up to 3 times too large where one direction dominates)
  // exceeds the largest eigenvalue this thread has found so far: the result is the exact maximum,
  // and the eigen-solves are few. Gershgorin's bound alone took 3-18 % more steps than this in the
  // stress suite's fine columns and filled tank. Cost: the forces' phase 0.75 -> 1.1 s over 139
  // steps of DamBreak at r = 0.0125, 2 threads: 2.4 ms of a 77-80 ms step (an eigen-solve per
  // particle in a pass of its own: 11 ms).
  if constexpr (kPackedPairSums) {
    ctx.paddedFluidNeighbors.expectBuiltFor(f.size(), "Viscosity_Standard");
    // The slots of packedFluidSumWithRate: (x, y, z, m / rho) and (v, 0).
    packSlots(positionsVolumes_, f.size(), [&](std::size_t j, Real* s) {
      s[0] = f.positions[j][0], s[1] = f.positions[j][1], s[2] = f.positions[j][2], s[3] = f.masses[j] / f.densities[j];
    });
    packSlots(velocities_, f.size(), [&](std::size_t j, Real* s) {
      s[0] = f.velocities[j][0], s[1] = f.velocities[j][1], s[2] = f.velocities[j][2], s[3] = 0;
    });
  } else {
    fluidVolumes(f, positionsVolumes_);  // here only V_j, one per particle
  }
  const Real largest = parallelReduce(ctx.fluidNeighbors.work, f.size(), Real(0), [](Real& into, Real from) { into = std::max(into, from); },
                                      [&](std::size_t i, Real& largestSoFar) {
    const Real rhoi = f.densities[i];
    Real rate[6] = {0, 0, 0, 0, 0, 0};  // 2 F_i + B_i without the factor 10 / rho_i: xx yy zz xy xz yz
    // ViscosityLaplacian.h: fluid and boundary terms.
    Vector3r a = (kLaplacianFactor * viscosity_ * rho0 / rhoi) * (kPackedPairSums ? packedFluidSumWithRate(ctx.paddedFluidNeighbors, i, positionsVolumes_.data(), velocities_.data(), eps, rate)
                                                            : fluidSumWithRate(f, ctx.fluidNeighbors, i, positionsVolumes_.data(), eps, rate));
    for (Real& entry : rate) entry *= Real(2) * viscosity_ * rho0;
    if (boundary) {
      const Vector3r xi = f.positions[i];
      a += (kLaplacianFactor * boundaryViscosity_ / rhoi) *
           boundarySum(ctx.boundary, ctx.boundaryNeighbors, i, xi, f.velocities[i], eps, true);
      const NeighborLists& bn = ctx.boundaryNeighbors;
      for (Index e = bn.begin(i); e < bn.end(i); ++e) {
        const Index k = bn.indices[e];
        const Vector3r xik = xi - ctx.boundary.positions[k];
        // As fluidSumWithRate: -x grad W^T, grad W parallel to x.
        const Vector3r g = (-boundaryViscosity_ * ctx.boundary.masses[k] / (xik.squaredNorm() + eps)) * bn.gradW[e];
        rate[0] += xik[0] * g[0];
        rate[1] += xik[1] * g[1];
        rate[2] += xik[2] * g[2];
        rate[3] += xik[0] * g[1];
        rate[4] += xik[0] * g[2];
        rate[5] += xik[1] * g[2];
      }
    }
    f.accelerations[i] += a;
    const Real rowX = std::abs(rate[0]) + std::abs(rate[3]) + std::abs(rate[4]);
    const Real rowY = std::abs(rate[3]) + std::abs(rate[1]) + std::abs(rate[5]);
    const Real rowZ = std::abs(rate[4]) + std::abs(rate[5]) + std::abs(rate[2]);
    const Real scale = kLaplacianFactor / rhoi;
    if (!(scale * std::max({rowX, rowY, rowZ}) > largestSoFar)) return;
    Matrix3r m;
    m << rate[0], rate[3], rate[4], rate[3], rate[1], rate[5], rate[4], rate[5], rate[2];
    Eigen::SelfAdjointEigenSolver<Matrix3r> eig;
    eig.computeDirect(m, Eigen::EigenvaluesOnly);
    largestSoFar = std::max(largestSoFar, scale * eig.eigenvalues()[2]);
  });
  stepLimit_ = largest > 0 ? Real(2) / largest : std::numeric_limits<Real>::infinity();
}

}  // namespace consph
