#include "Plugins/Viscosity/Viscosity_Standard.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
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
  const Real largest = parallelMax(f.size(), Real(0), [&](std::size_t i) {
    const Real rhoi = f.densities[i];
    const Vector3r xi = f.positions[i];
    // ViscosityLaplacian.h: fluid and boundary terms.
    Vector3r a = (kLaplacianFactor * viscosity_ * rho0 / rhoi) * fluidSum(f, ctx.fluidNeighbors, i, f.velocities.data(), eps);
    Matrix3r rate = Matrix3r::Zero();  // 2 F_i + B_i without the factors 10 nu / rho_i
    const NeighborLists& fn = ctx.fluidNeighbors;
    for (Index e = fn.begin(i); e < fn.end(i); ++e) {
      const Index j = fn.indices[e];
      const Vector3r xij = xi - f.positions[j];
      const Real r2 = xij.squaredNorm();
      if (r2 <= 0) continue;
      const Real w = -Real(2) * viscosity_ * rho0 * (f.masses[j] / f.densities[j]) * xij.dot(fn.gradW[e]) / ((r2 + eps) * r2);
      rate.noalias() += w * xij * xij.transpose();
    }
    if (boundary) {
      a += (kLaplacianFactor * boundaryViscosity_ / rhoi) *
           boundarySum(ctx.boundary, ctx.boundaryNeighbors, i, xi, f.velocities[i], eps, true);
      const NeighborLists& bn = ctx.boundaryNeighbors;
      for (Index e = bn.begin(i); e < bn.end(i); ++e) {
        const Index k = bn.indices[e];
        const Vector3r xik = xi - ctx.boundary.positions[k];
        const Real r2 = xik.squaredNorm();
        if (r2 <= 0) continue;
        const Real w = -boundaryViscosity_ * ctx.boundary.masses[k] * xik.dot(bn.gradW[e]) / ((r2 + eps) * r2);
        rate.noalias() += w * xik * xik.transpose();
      }
    }
    f.accelerations[i] += a;
    // The largest eigenvalue of the symmetric 3 x 3 rate matrix.
    Eigen::SelfAdjointEigenSolver<Matrix3r> eig;
    eig.computeDirect(rate, Eigen::EigenvaluesOnly);
    return kLaplacianFactor / rhoi * std::max(eig.eigenvalues()[2], Real(0));
  });
  stepLimit_ = largest > 0 ? Real(2) / largest : std::numeric_limits<Real>::infinity();
}

}  // namespace consph
