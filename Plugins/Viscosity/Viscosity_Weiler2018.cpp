#include "Plugins/Viscosity/Viscosity_Weiler2018.h"

#include <Eigen/LU>  // 3x3 inverse
#include <span>

#include "Plugins/Viscosity/ViscosityLaplacian.h"
#include "Simulation/ParamBinding.h"
#include "Simulation/PluginRegistry.h"
#include "Utilities/ParallelFor.h"

namespace consph {

namespace {
const PluginRegistration<NonPressureForce> registration{
    "Weiler2018", "implicit viscosity solved by matrix-free conjugate gradient (Weiler et al. 2018), kinematic viscosity in m^2/s",
    Viscosity_Weiler2018::parameters(), [](const Params& p, const PluginContext& c) -> std::unique_ptr<NonPressureForce> {
      return std::make_unique<Viscosity_Weiler2018>(p, *c.fluid);
    }};
}  // namespace

const BoundParams<Viscosity_Weiler2018>& Viscosity_Weiler2018::bound() {
  static const BoundParams<Viscosity_Weiler2018> table{
      bind({"viscosity", ParamType::Real, 0.01, "kinematic viscosity nu of the fluid, m^2/s", 0, 1e6},
           &Viscosity_Weiler2018::viscosity_),
      bind({"boundaryViscosity", ParamType::Real, 0.0, "kinematic viscosity towards boundaries, m^2/s (0: free slip)", 0, 1e6},
           &Viscosity_Weiler2018::boundaryViscosity_),
      bind({"maxError", ParamType::Real, 0.01,
            "CG stops at residual below this fraction of the viscous change |b - A v| (dimensionless)", 1e-12, 1},
           &Viscosity_Weiler2018::maxError_),
      bind({"maxIterations", ParamType::Int, 100, "CG iteration cap per step", 1, 100000}, &Viscosity_Weiler2018::maxIterations_),
  };
  return table;
}

std::vector<ParamSpec> Viscosity_Weiler2018::parameters() { return bound().specs(); }

Viscosity_Weiler2018::Viscosity_Weiler2018(const Params& p, FluidModel& fluid)
    : velocityChange_(fluid.fields().add<Vector3r>("viscosityVelocityChange", FieldSorted, Vector3r::Zero())) {
  bound().assign(p, *this);
}

void Viscosity_Weiler2018::addAccelerations(StepContext& ctx) {
  using namespace viscosity;
  const FluidView& f = ctx.fluid;
  const BoundaryView& b = ctx.boundary;
  const auto& fn = ctx.fluidNeighbors;
  const auto& bn = ctx.boundaryNeighbors;
  const std::size_t n = f.size();
  const Real dt = ctx.dt;  // the previous step's dt: see the header
  const Real eps = regularisation(ctx.kernel), rho0 = f.density0();
  const Real cFluid = dt * kLaplacianFactor * viscosity_ * rho0, cBoundary = dt * kLaplacianFactor * boundaryViscosity_;
  const bool boundary = boundaryViscosity_ > 0;
  rhs_.resize(f.size());
  solution_.resize(f.size());
  inverseDiagonal_.resize(f.size());
  // Slots (x, y, z, V = m / rho) for packedFluidSum (V alone for fluidSum without
  // kPackedPairSums): the densities stay fixed through the solve.
  if constexpr (kPackedPairSums) {
    ctx.paddedFluidNeighbors.expectBuiltFor(n, "Viscosity_Weiler2018");
    packSlots(positionsVolumes_, n, [&](std::size_t j, Real* s) {
      s[0] = f.positions[j][0], s[1] = f.positions[j][1], s[2] = f.positions[j][2], s[3] = f.masses[j] / f.densities[j];
    });
  } else {
    fluidVolumes(f, positionsVolumes_);
  }
  const std::size_t volumeStride = kPackedPairSums ? 4 : 1;

  // Right-hand side m_i (v_i - dt nu_b / rho_i sum_k m~_k K_ik v_k), warm start, and the 3x3
  // diagonal blocks m_i (I - dt L_ii) of the preconditioner (K_ij u = (u . x_ij) grad W_ij / (..)).
  parallelFor(n, [&](std::size_t i) {
    const Vector3r xi = f.positions[i], vi = f.velocities[i];
    const Real rhoi = f.densities[i], mi = f.masses[i];
    Vector3r bi = vi;
    Matrix3r d = Matrix3r::Zero();
    for (Index e = fn.begin(i); e < fn.end(i); ++e) {
      const Index j = fn.indices[e];
      const Vector3r xij = xi - f.positions[j];
      const Real volume = positionsVolumes_[volumeStride * std::size_t(j) + (volumeStride - 1)];
      d += (volume / (xij.squaredNorm() + eps)) * (fn.gradient(e, xij) * xij.transpose());
    }
    d *= cFluid / rhoi;
    if (boundary) {
      Matrix3r db = Matrix3r::Zero();
      for (Index e = bn.begin(i); e < bn.end(i); ++e) {
        const Index k = bn.indices[e];
        const Vector3r xik = xi - b.positions[k];
        db += (b.masses[k] / (xik.squaredNorm() + eps)) * (bn.gradW[e] * xik.transpose());
        bi += (cBoundary / rhoi) * b.masses[k] * (b.velocities[k].dot(xik) / (xik.squaredNorm() + eps)) * bn.gradW[e];
      }
      d += (cBoundary / rhoi) * db;
    }
    rhs_[i] = mi * bi;
    inverseDiagonal_[i] = (mi * (Matrix3r::Identity() - d)).inverse();
    solution_[i] = vi + velocityChange_[i];
  });

  // A x = m_i (x_i - dt nu (rho0 / rho_i) sum_j (m_j / rho_j) K_ij x_ij - dt nu_b / rho_i sum_k m~_k K_ik x_i).
  auto applyA = [&](std::span<const Vector3r> x, std::vector<Vector3r>& out) {
    if constexpr (kPackedPairSums)
      packSlots(fieldSlots_, n, [&](std::size_t j, Real* s) { s[0] = x[j][0], s[1] = x[j][1], s[2] = x[j][2], s[3] = 0; });
    parallelFor(fn.work, n, [&](std::size_t i) {
      const Real rhoi = f.densities[i];
      Vector3r lx = (cFluid / rhoi) * (kPackedPairSums ? packedFluidSum(ctx.paddedFluidNeighbors, i, positionsVolumes_.data(), fieldSlots_.data(), eps)
                                                       : fluidSum(f, fn, i, x.data(), positionsVolumes_.data(), eps));
      if (boundary) lx += (cBoundary / rhoi) * boundarySum(b, bn, i, f.positions[i], x[i], eps, false);
      out[i] = f.masses[i] * (x[i] - lx);
    });
  };
  auto applyPreconditioner = [&](const std::vector<Vector3r>& r, std::vector<Vector3r>& out) {
    parallelFor(n, [&](std::size_t i) { out[i] = inverseDiagonal_[i] * r[i]; });
  };
  // Tolerance relative to the viscous change itself, |b - A v| (the residual of "no viscosity"):
  // a tolerance relative to |b| ~ |m v| (Eigen's, SPlisHSPlasH's) accepts the warm start without
  // a single iteration whenever nu dt |L v| < maxError |v|, i.e. almost always at nu = 0.01.
  workspace_.ap.resize(f.size());
  applyA(f.velocities, workspace_.ap);
  const Real change2 = parallelSum<Real>(n, [&](std::size_t i) { return (rhs_[i] - workspace_.ap[i]).squaredNorm(); });
  const Real tolerance = maxError_ * std::sqrt(change2);
  if (change2 == Real(0)) {  // rest, rigid motion: v' = v exactly
    solution_.assign(f.velocities.begin(), f.velocities.end());
    last_ = ConjugateGradientResult{0, 0, true};
  } else {
    last_ = solveConjugateGradient(applyA, applyPreconditioner, rhs_, solution_, tolerance, maxIterations_, workspace_);
  }
  if (!last_.converged && ++capHits_ <= 5 && ctx.log)
    ctx.log(LogLevel::Warning, "step " + std::to_string(ctx.step) + ": Weiler2018 viscosity hit its iteration cap (" +
                                   std::to_string(maxIterations_) + ", residual " +
                                   std::to_string(last_.residual / std::sqrt(change2)) + " of the viscous change)");

  // a_i += (v'_i - v_i) / dt; keep v' - v for the next warm start.
  const Real invDt = Real(1) / dt;
  parallelFor(n, [&](std::size_t i) {
    velocityChange_[i] = solution_[i] - f.velocities[i];
    f.accelerations[i] += invDt * velocityChange_[i];
  });
}

}  // namespace consph
