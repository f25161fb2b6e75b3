// Interface of non-pressure forces (viscosity, vorticity, drag, surface tension, ...).
#pragma once
#include "Simulation/StepContext.h"

namespace consph {

class NonPressureForce {
 public:
  virtual ~NonPressureForce() = default;
  // Adds this force's acceleration to ctx.fluid.accelerations (which already holds gravity and
  // the forces before this one in scene order). Runs before the pressure solve, with the
  // densities of this step; ctx.dt is the previous step's until the CFL step is chosen.
  virtual void addAccelerations(StepContext& ctx) = 0;
};

}  // namespace consph
