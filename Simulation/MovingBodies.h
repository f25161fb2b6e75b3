// The scene's moving boundary objects as the kernel sees them: dynamic rigid bodies (two-way
// coupled with the fluid, paper Section 3.5, Eq. (35)), animated bodies and hinges. The kernel
// hands them the impulses the pressure solver's boundary term gave their samples and takes back
// their poses, which it gives the boundary model: the model is the only writer of its samples'
// positions (BoundaryModel::follow). One step reads
//   bodies.takeFluidImpulses(...)  ->  bodies.advance(...)  ->  model.follow(bodies.poses(true)).
// Within a pressure solve they also answer as a BodyResponse (trial velocities of their samples,
// Simulation/BodyResponse.h). Implemented by Boundary/RigidBodySystem; created by
// makeMovingBodies, which that implementation defines.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "Simulation/BodyResponse.h"
#include "Simulation/BoundaryModel.h"
#include "Utilities/Log.h"
#include "Utilities/TriangleMesh.h"

namespace consph {

// One moving body's state (copies, for the kernel's checks, probes, checkpoints and output).
struct MovingBodyState {
  std::string name;
  BodyMotion motion = BodyMotion::Animated;
  Index object = 0;  // its boundary object (BoundarySamples::bodies)
  Real mass = 0;     // kg (dynamic bodies)
  Real reach = 0;    // its farthest surface point from the centre x, m
  Vector3r x = Vector3r::Zero(), x0 = Vector3r::Zero();  // centre (of mass), now and at t = 0
  Quaternionr q = Quaternionr::Identity();                // body -> world
  Vector3r v = Vector3r::Zero(), w = Vector3r::Zero();    // m/s, rad/s
  Vector3r fluidForce = Vector3r::Zero(), fluidTorque = Vector3r::Zero();  // over the last step, N, N m about x
};

// Two objects whose sample layers overlap (a start-up check), one of them a free dynamic body.
struct BodyOverlap {
  Index objectA = 0, objectB = 0;
  Real depth = 0;  // m
};

class MovingBodies : public BodyResponse {
 public:
  bool hasDynamic() const { return dynamicCount() > 0; }
  virtual std::size_t dynamicCount() const = 0;
  virtual bool hasFreeDynamic() const = 0;
  virtual std::size_t count() const = 0;
  virtual MovingBodyState state(std::size_t body) const = 0;
  // A checkpoint's state back (position, orientation, velocities, fluid force and torque).
  virtual void restoreState(std::size_t body, const MovingBodyState& state) = 0;

  // Eq. (35): the impulse the fluid gave each sample of a moving body (pairImpulses[e] for the
  // pair e = (i, k) of `lists`), summed into impulse and angular impulse per body.
  virtual void takeFluidImpulses(const NeighborLists& lists, const std::vector<Vector3r>& fluidPositions,
                                 const BoundarySamples& samples, const std::vector<Vector3r>& pairImpulses) = 0;
  // One step of the bodies with the impulses taken (and gravity, rigid contact on `samples`);
  // a light body shares them with the fluid touching it, whose velocities change too.
  virtual void advance(Real dt, const Vector3r& gravity, const BoundarySamples& samples,
                       const std::vector<Vector3r>& fluidPositions, const std::vector<Real>& fluidMasses,
                       std::vector<Vector3r>& fluidVelocities) = 0;
  // Every moving object's pose for the boundary model; `onlyChanged`: only those whose state
  // changed since the last call (a body at rest costs nothing per step).
  virtual const std::vector<PoseUpdate>& poses(bool onlyChanged) = 0;

  // Object pairs whose sample layers overlap by more than `tolerance` m now.
  virtual std::vector<BodyOverlap> overlaps(const BoundarySamples& samples, Real tolerance) = 0;
  // The largest speed rigid contact pushes overlapping bodies apart at, m/s (the warning says it).
  virtual Real maxPushOutSpeed() const = 0;

  // Output: bodies.csv (header, then one row per body) and every body's surface where it is now
  // (one mesh, each vertex's object index and velocity).
  virtual std::string csvHeader() const = 0;
  virtual std::string csvRows(double time) const = 0;
  virtual void worldMeshes(TriangleMesh& mesh, std::vector<Index>& object, std::vector<Vector3r>& velocity) const = 0;
};

// The moving bodies of `objects` (null when every object is static): `model` is initialised
// (its samples, layer depths, whether it is implicit); r the particle radius; rho0 the fluid's
// rest density (added mass).
std::unique_ptr<MovingBodies> makeMovingBodies(const std::vector<BoundaryObject>& objects, const BoundaryModel& model,
                                               Real particleRadius, Real fluidDensity, const LogSink& log);

}  // namespace consph
