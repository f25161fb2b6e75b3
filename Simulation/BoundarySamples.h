// The one view of the boundary that solvers and forces see, whatever the boundary model:
// sampling points k with position, velocity and mass m~_k = rho0 V_k (Eq. 14). Particle
// boundaries keep them for the whole run; implicit models may regenerate them every step.
#pragma once
#include <vector>

#include "Simulation/Common.h"

namespace consph {

struct BoundarySamples {
  std::vector<Vector3r> positions;   // x_k (m)
  std::vector<Vector3r> velocities;  // v_k (m/s), the body's velocity at x_k
  std::vector<Real> masses;          // m~_k = rho0 V_k (kg), Eq. (14)
  std::vector<Index> bodies;         // index of the boundary object k belongs to

  std::size_t size() const { return positions.size(); }
  void resize(std::size_t n) {
    positions.resize(n, Vector3r::Zero());
    velocities.resize(n, Vector3r::Zero());
    masses.resize(n, Real(0));
    bodies.resize(n, Index(0));
  }
};

}  // namespace consph
