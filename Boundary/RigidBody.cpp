#include "Boundary/RigidBody.h"

#include <Eigen/Geometry>

namespace consph {

void RigidBody::applyImpulses(const Vector3r& J, const Vector3r& L, Real dt) {
  v += J / mass;
  const Matrix3r R = rotation();
  const Matrix3r I = R * inertiaBody * R.transpose();
  w += invInertiaWorld() * (L - dt * w.cross(I * w));
}

void RigidBody::advance(Real dt) {
  x += dt * v;
  const Real angle = w.norm() * dt;
  if (angle > 0) q = Quaternionr(Eigen::AngleAxis<Real>(angle, w.normalized())) * q;
  q.normalize();
}

void RigidBody::rotateAbout(const Vector3r& point, const Vector3r& axis, Real angle) {
  const Quaternionr dq(Eigen::AngleAxis<Real>(angle, axis));
  x = point + dq * (x - point);
  q = dq * q;
  q.normalize();
}

}  // namespace consph
