// Interface of pressure solvers (DFSPH, IISPH, WCSPH, ...).
#pragma once
#include <limits>
#include <vector>

#include "Simulation/StepContext.h"
#include "Utilities/Error.h"

namespace consph {

struct PressureSolverStats {
  int pressureIterations = 0;    // last step
  int divergenceIterations = 0;  // last step
  Real densityError = 0;         // last predicted average compression (fraction of rho0)
  Real divergenceError = 0;      // last average divergence error (fraction of rho0)
  // last predicted compression of the most compressed particle outside a closing gap (fraction of
  // rho0; DFSPH)
  Real largestDensityError = 0;
  bool hitIterationCap = false;  // last step ended at maxIterations without converging
};

class PressureSolver {
 public:
  virtual ~PressureSolver() = default;
  // After densities, before non-pressure forces (DFSPH's divergence solve lives here).
  virtual void beforeNonPressureForces(StepContext& ctx) {}
  // Called with v = v* = v(t) + dt a^np (Eq. 4); leaves v(t + dt) in fluid.velocities and the
  // pressure in fluid.pressures.
  virtual void solve(StepContext& ctx) = 0;
  // Two-way coupling with dynamic bodies (paper Eq. (35)): for every pair e = (i, k) of
  // ctx.boundaryNeighbors, the impulse (N s) that this step's pressure solve(s) gave boundary
  // sample k: exactly minus the impulse fluid particle i received from k through the solver's
  // boundary term, so the bodies gain the momentum the fluid lost. Called after solve().
  virtual void boundaryImpulses(const StepContext& ctx, std::vector<Vector3r>& impulsePerPair) const {
    throw SimulationError("this pressure solver does not report boundary impulses, which dynamic bodies need");
  }
  // The largest time step an explicit solver is stable at, s (infinite for the implicit ones):
  // part of the default time-step cap, like NonPressureForce::maxStableTimeStep.
  virtual Real maxStableTimeStep(Real particleRadius, Real density0) const { return std::numeric_limits<Real>::infinity(); }
  // Whether the solver reads ctx.paddedFluidNeighbors (as NonPressureForce::readsPaddedNeighbors).
  virtual bool readsPaddedNeighbors() const { return false; }
  const PressureSolverStats& stats() const { return stats_; }

 protected:
  PressureSolverStats stats_;
};

}  // namespace consph
