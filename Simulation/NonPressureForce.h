// Interface of non-pressure forces (viscosity, vorticity, drag, surface tension, ...).
#pragma once
#include <limits>

#include "Simulation/StepContext.h"

namespace consph {

class NonPressureForce {
 public:
  virtual ~NonPressureForce() = default;
  // Adds this force's acceleration to ctx.fluid.accelerations (which already holds gravity and
  // the forces before this one in scene order). Runs before the pressure solve, with the
  // densities of this step; ctx.dt is the previous step's until the CFL step is chosen.
  virtual void addAccelerations(StepContext& ctx) = 0;
  // The largest time step at which this force stays stable, s (an explicit diffusion's limit);
  // infinity when it sets none. Bounds the default maximum step (Simulation's timeStepCap).
  virtual Real maxStableTimeStep(const CubicSplineKernel&) const { return std::numeric_limits<Real>::infinity(); }
  // The largest stable step for the particles the last addAccelerations saw, s; infinity when it
  // sets none. Bounds every step like the CFL condition (a user's maxTimeStep included): an
  // explicit diffusion is unstable where its local coefficient exceeds what
  // maxStableTimeStep assumed (a free surface's sparse, light particles).
  virtual Real stepLimit() const { return std::numeric_limits<Real>::infinity(); }
  // Whether addAccelerations reads ctx.paddedFluidNeighbors: the simulation builds them only
  // when a plugin of the scene does (Simulation/PaddedNeighborLists.h).
  virtual bool readsPaddedNeighbors() const { return false; }
};

}  // namespace consph
