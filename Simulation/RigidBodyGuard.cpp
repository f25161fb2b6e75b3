#include "Simulation/RigidBodyGuard.h"

#include <algorithm>
#include <sstream>

#include "Utilities/AxisAlignedBox.h"
#include "Utilities/Error.h"

namespace consph {

RigidBodyGuard::Limits RigidBodyGuard::limitsFor(Real speedScale, bool hasDomain, const Vector3r& domainMin,
                                                 const Vector3r& domainMax) {
  Limits l;
  l.maxSpeed = kSpeedFactor * std::max(speedScale, kMinSpeedScale);
  l.hasDomain = hasDomain;
  l.domainMin = domainMin;
  l.domainMax = domainMax;
  return l;
}

RigidBodyGuard::RigidBodyGuard(std::vector<std::string> labels, const Limits& limits)
    : labels_(std::move(labels)), limits_(limits) {}

void RigidBodyGuard::check(const MovingBodies& bodies, std::size_t step, double time) const {
  for (std::size_t i = 0; i < bodies.count(); ++i) {
    const MovingBodyState b = bodies.state(i);
    if (b.motion != BodyMotion::Dynamic) continue;  // animated bodies move as prescribed
    std::ostringstream s;
    s << "step " << step << ", t = " << time << " s: dynamic body " << labels_[i];
    if (!b.x.allFinite() || !b.v.allFinite() || !b.w.allFinite() || !b.q.coeffs().allFinite())
      throw SimulationError(s.str() + " has a non-finite position, orientation or velocity (NaN/inf): the simulation blew up");
    const Real speed = b.v.norm() + b.w.norm() * b.reach;
    if (speed > limits_.maxSpeed) {
      s << " moves at " << speed << " m/s (|v| + |w| R, v = " << b.v.norm() << " m/s, w = " << b.w.norm()
        << " rad/s), beyond the scene's bound of " << limits_.maxSpeed << " m/s (" << kSpeedFactor
        << " x its speed scale sqrt(v0^2 + 2 g H)): the body blew up (a body much lighter or heavier than the fluid"
           " needs a smaller time step)";
      throw SimulationError(s.str());
    }
    if (limits_.hasDomain && !insideBox(b.x, limits_.domainMin, limits_.domainMax)) {
      s << " left the domain: its centre of mass is at (" << b.x[0] << ", " << b.x[1] << ", " << b.x[2]
        << "): it passed through a boundary or the simulation blew up";
      throw SimulationError(s.str());
    }
  }
}

}  // namespace consph
