// Stops a run whose dynamic rigid body blew up, as Simulation::checkState does for the fluid:
// a non-finite state, a surface point faster than the scene's bound, or the centre of mass
// outside the domain -> SimulationError naming the body, the step and the time.
//
// Speed bound: kSpeedFactor times the scene's speed scale U = sqrt(v0^2 + 2 |g| H)
// (Simulation/SpeedScale.h), at least kSpeedFactor times 1 m/s. A body driven by gravity and a
// fluid that gravity drives never gets near it; one that does is far outside what the time step
// resolves (a body of 1e-6 rho0 under water: buoyancy 1e9 g, 4e7 m/s within a second).
#pragma once
#include <string>
#include <vector>

#include "Simulation/MovingBodies.h"

namespace consph {

class RigidBodyGuard {
 public:
  static constexpr Real kSpeedFactor = 10;
  static constexpr Real kMinSpeedScale = 1;  // m/s: a bound also when nothing moves at start (no gravity)

  struct Limits {
    Real maxSpeed = 0;  // m/s, surface speed |v| + |w| R
    bool hasDomain = false;
    Vector3r domainMin = Vector3r::Zero(), domainMax = Vector3r::Zero();
  };
  // Limits from the scene's speed scale U (m/s) and the domain the bodies must stay in.
  static Limits limitsFor(Real speedScale, bool hasDomain, const Vector3r& domainMin, const Vector3r& domainMax);

  // `labels[b]`: how messages name body b ("'box' (boundaries[1])").
  RigidBodyGuard(std::vector<std::string> labels, const Limits& limits);

  // Throws SimulationError for the first dynamic body that blew up.
  void check(const MovingBodies& bodies, std::size_t step, double time) const;
  const Limits& limits() const { return limits_; }

 private:
  std::vector<std::string> labels_;
  Limits limits_;
};

}  // namespace consph
