// Divergence-free SPH after
//   J. Bender, D. Koschier: Divergence-Free SPH for Incompressible and Viscous Fluids.
//   IEEE Transactions on Visualization and Computer Graphics 23(3), 2017,
// with the boundary handling of
//   J. Bender, L. Westhofen, S. R. Jeske: Consistent SPH Rigid-Fluid Coupling. VMV 2023,
// or mirroring / MLS extrapolation (BoundaryPressureTreatment), in both solves.
// Unknowns are beta_i = p_i / rho_i^2 = lambda_i / rho_i (paper Section 3.4.1).
#pragma once
#include <vector>

#include "Plugins/Pressure/BoundaryPressureTreatment.h"
#include "Plugins/Pressure/PackedPairSums.h"
#include "Plugins/Pressure/SphPressureTerms.h"
#include "Simulation/Params.h"
#include "Simulation/PressureSolver.h"

namespace consph {

template <class Settings>
class BoundParams;

class DFSPH final : public PressureSolver {
 public:
  DFSPH(const Params& params, FluidModel& fluid, BoundaryPressure treatment = BoundaryPressure::Consistent);
  void beforeNonPressureForces(StepContext& ctx) override;
  void solve(StepContext& ctx) override;
  void boundaryImpulses(const StepContext& ctx, std::vector<Vector3r>& impulsePerPair) const override;
  static std::vector<ParamSpec> parameters();
  bool readsPaddedNeighbors() const override { return kPackedPairSums; }  // PackedPairSums.h

 private:
  struct Settings {
    Real maxError;            // fraction of rho0 (average compression)
    Real maxErrorParticle;    // fraction of rho0 (any one particle's compression), 0: off
    Real maxErrorDivergence;  // fraction of rho0 per time step
    int minIterations, maxIterations, maxIterationsDivergence;
    bool divergenceSolver, warmStart;
    Real overlapReliefSpeed;  // m/s, 0: off
    DensityRelaxation densityRelaxation;  // driftTarget's relaxation time (densityRelaxationTime)
    enum class BodyCoupling { Auto, Iterated, Explicit } bodyCoupling;  // Simulation/BodyResponse.h
  } settings_;
  using BodyCoupling = Settings::BodyCoupling;
  // The parameters, each declared once with its place in settings_ (Simulation/ParamBinding.h).
  static const BoundParams<Settings>& bound();
  // Whether this step's free bodies answer within the iterations (bodyCoupling, resolved).
  bool iteratesBodies(const StepContext& ctx) const;

  void computeDiagonal(StepContext& ctx);
  // Applies (a scaled half of) last step's accumulated beta, or zeroes it.
  void warmStart(StepContext& ctx, std::vector<Real>& beta, Real dtScale);
  // Source of the density solve (rho* - rho0, Eq. 6) or of the divergence solve (D rho / Dt);
  // returns the average error as a fraction of rho0 (times dt for divergence), and the largest
  // single particle's in `largest` (density solve only).
  Real computeSources(StepContext& ctx, bool divergence, Real* largest = nullptr);
  // v_i -= dt (sum_j m_j (k_i + k_j) grad W_ij + boundary term), Eqs. (16)/(33); `accumulated`
  // is the beta the velocities already carry (extrapolation fits p_k to accumulated + k), and k
  // is added to it in the same loop (one parallel region less per iteration).
  void applyPressureIncrement(StepContext& ctx, const std::vector<Real>& k, std::vector<Real>* accumulated);
  // The reaction per boundary pair of what the solves applied so far (Eq. 35): the divergence
  // solve's beta and p_k `divergenceP` over `divergenceDt` (0: none), and the density solve's
  // over ctx.dt when `withDensity`.
  void pairImpulses(const StepContext& ctx, Real divergenceDt, const std::vector<Real>& divergenceP, bool withDensity,
                    std::vector<Vector3r>& impulsePerPair) const;
  // pairImpulses' value for the pair e of fluid particle i.
  Vector3r pairImpulse(const StepContext& ctx, Index i, Index e, Real divergenceDt, const std::vector<Real>& divergenceP,
                       bool withDensity) const {
    const FluidView& f = ctx.fluid;
    const Index k = ctx.boundaryNeighbors.indices[e];
    const Real rho2 = f.densities[i] * f.densities[i];
    const Real betaDiv = divergenceBeta_[i], betaDen = densityBeta_[i];
    Real c = withDensity ? ctx.dt * treatment_.pairFactor(k, betaDen, betaDen * rho2, treatment_.boundaryPressures()) : Real(0);
    if (divergenceDt > 0) c += divergenceDt * treatment_.pairFactor(k, betaDiv, betaDiv * rho2, divergenceP);
    return (f.masses[i] * ctx.boundary.masses[k] * c) * ctx.boundaryNeighbors.gradW[e];
  }
  // Iterated coupling: the free bodies' samples move as the impulses so far would move them.
  void letBodiesRespond(StepContext& ctx, bool densitySolve);

  std::vector<Real>& densityBeta_;     // accumulated beta of the density solve (warm start), sorted field
  std::vector<Real>& divergenceBeta_;  // accumulated beta of the divergence solve, sorted field
  std::vector<Real> invDiagonal_;      // 1 / D_i (Eq. 32 without the -dt / rho_i^2 factor)
  std::vector<Real> increment_;        // beta increment of the current iteration
  std::vector<unsigned char> closingGap_;  // maxErrorParticle: 1 where two objects close in from opposite sides
  // The slots the fluid sums of every iteration read (PackedPairSums.h), packed by computeDiagonal
  // (positions), applyPressureIncrement (m_j beta_j, and the velocities it changes) or
  // computeSources (the velocities, when no increment has written them since the forces); and
  // G_i = sum_j m_j grad W_ij of the pressure term and the density rate, from computeDiagonal.
  PackedParticles packed_;
  bool velocitiesPacked_ = false;  // packed_.momenta hold the fluid's velocities
  std::vector<Vector3r> massGradientSums_;
  BoundaryPressureTreatment treatment_;
  Real divergenceDt_ = 0;                 // the time step the divergence solve of this step used
  std::vector<Real> divergenceBoundaryP_; // extrapolation: p_k of the divergence solve (its total)
  std::vector<Vector3r> trialImpulses_;   // letBodiesRespond's per-pair impulses
};

}  // namespace consph
