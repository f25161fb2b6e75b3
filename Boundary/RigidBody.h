// State and time integration of one rigid body: position of the centre of mass, orientation
// quaternion, linear and angular velocity. Semi-implicit (symplectic) Euler like the fluid:
// velocities from this step's impulses first, positions with the new velocities.
#pragma once
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "Simulation/BoundaryModel.h"

namespace consph {

struct RigidBody {
  std::string name;
  BodyMotion motion = BodyMotion::Static;
  Index object = 0;  // index of its boundary object (BoundarySamples::bodies)

  Real mass = 0;                                  // kg
  Real volume = 0;                                // m^3 (dynamic bodies)
  Matrix3r inertiaBody = Matrix3r::Identity();    // about the centre of mass, body frame, kg m^2
  Matrix3r invInertiaBody = Matrix3r::Identity();

  Vector3r x = Vector3r::Zero();  // centre of mass, m
  Vector3r x0 = Vector3r::Zero();  // its position at t = 0 (the body frame's origin in the scene's coordinates)
  Quaternionr q = Quaternionr::Identity();  // body -> world; the body frame is the world frame at t = 0
  Vector3r v = Vector3r::Zero();  // m/s
  Vector3r w = Vector3r::Zero();  // rad/s

  // Average fluid force and torque (about x) over the last step, N and N m (output).
  Vector3r fluidForce = Vector3r::Zero(), fluidTorque = Vector3r::Zero();

  std::vector<Index> samples;          // its boundary samples k (the model moves them: BoundaryModel::follow)
  // Its points in the contact surface (RigidBodySystem::contactSurface): its boundary samples
  // where the model has a sample layer, else points on its mesh (volume maps), with their
  // positions in the body frame relative to x (only for the latter).
  std::vector<Index> contactSamples;
  std::vector<Vector3r> localContactSamples;
  TriangleMesh localMesh;              // its surface in the body frame, relative to x (output)
  Real reach = 0;                      // its farthest surface point from x, m (the guard's |w| R)

  Matrix3r rotation() const { return q.toRotationMatrix(); }
  Matrix3r invInertiaWorld() const {
    const Matrix3r R = rotation();
    return R * invInertiaBody * R.transpose();
  }
  ObjectPose pose() const { return {rotation(), x, x0, v, w}; }
  Vector3r velocityAt(const Vector3r& p) const { return v + w.cross(p - x); }

  // A free body: v += J / m, w += I^-1 (L - dt w x I w) (gyroscopic term explicit),
  // for linear impulse J and angular impulse L about x.
  void applyImpulses(const Vector3r& J, const Vector3r& L, Real dt);
  // x += dt v, q <- exp(dt w) q (exact rotation for constant w, renormalised).
  void advance(Real dt);
  // A rotation by `angle` about the world axis through `point`.
  void rotateAbout(const Vector3r& point, const Vector3r& axis, Real angle);
};

}  // namespace consph
