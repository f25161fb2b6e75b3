#include "Simulation/SpeedScale.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace consph {

SpeedScale sceneSpeedScale(const SceneDescription& scene) {
  const Real g = scene.gravity.norm();
  // Height above the lowest point, measured against gravity (y for the usual [0, -9.81, 0]).
  const Vector3r up = g > 0 ? Vector3r(-scene.gravity / g) : Vector3r::UnitY();
  Real top = std::numeric_limits<Real>::lowest(), bottom = std::numeric_limits<Real>::max();
  Real bottomMoving = bottom;  // the lowest point of what moves (a floor when no static object is lower)
  Real v0 = 0;
  auto moving = [&](const Vector3r& x) {
    top = std::max(top, x.dot(up));
    bottomMoving = std::min(bottomMoving, x.dot(up));
  };
  for (const FluidDescription& f : scene.fluids) {
    for (const FluidBlock& b : f.blocks) {
      for (int c = 0; c < 8; ++c)
        moving(Vector3r(c & 1 ? b.max[0] : b.min[0], c & 2 ? b.max[1] : b.min[1], c & 4 ? b.max[2] : b.min[2]));
      v0 = std::max(v0, b.velocity.norm());
    }
    for (std::size_t i = 0; i < f.sourcePositions.size(); ++i) {
      moving(f.sourcePositions[i]);
      v0 = std::max(v0, f.sourceVelocities[i].norm());
    }
    for (const EmitterDescription& e : f.emitters) {
      moving(e.position);
      v0 = std::max(v0, e.speed);
    }
  }
  for (const BoundaryObject& o : scene.boundaries) {
    if (o.motion == BodyMotion::Static) {
      for (const Vector3r& x : o.mesh.vertices) bottom = std::min(bottom, x.dot(up));
      continue;
    }
    // A moving body's fastest surface point: |v| + |w| R, R its farthest vertex from the
    // vertices' centroid (a bound: the centre of mass lies inside their hull).
    Vector3r c = Vector3r::Zero();
    for (const Vector3r& x : o.mesh.vertices) c += x;
    c /= Real(std::max<std::size_t>(o.mesh.vertices.size(), 1));
    Real radius = 0;
    for (const Vector3r& x : o.mesh.vertices) {
      moving(x);
      radius = std::max(radius, (x - c).norm());
    }
    Real spin = o.angularVelocity.norm();
    if (o.hinge.enabled && o.hinge.motor) spin = std::max(spin, std::abs(o.hinge.targetVelocity));
    v0 = std::max(v0, o.velocity.norm() + spin * radius);
  }
  bottom = std::min(bottom, bottomMoving);
  SpeedScale s;
  s.fallHeight = top > bottom ? top - bottom : 0;
  s.initialSpeed = v0;
  s.speed = std::sqrt(v0 * v0 + 2 * g * s.fallHeight);
  return s;
}

}  // namespace consph
