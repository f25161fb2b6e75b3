// Where a resting fluid's first particle layer sits against a flat boundary: the distance D at
// which the layer's density, its share from the fluid lattice plus the boundary's share, is rest
// density. Boundary models use it to move their surface so that the resting fluid's surface
// (the layer's centres less half a spacing) lies on the mesh.
#pragma once
#include <functional>

#include "Simulation/Kernel.h"

namespace consph {

// rho / rho0 of a particle in the outer layer of a cubic lattice of spacing `spacing` from the
// lattice alone (the half-lattice, its own layer included): 0.8275 at d = 1.8566 r, h = 4r.
Real halfLatticeDensity(const CubicSplineKernel& kernel, Real spacing);

// D in [0, h] with fluidShare + boundaryShare(D) = 1 (bisection; boundaryShare falls with D):
// 0 if the layer is too dense even on the boundary, h if the fluid alone is already dense enough.
Real restDistance(Real fluidShare, Real supportRadius, const std::function<Real(Real)>& boundaryShare);

}  // namespace consph
