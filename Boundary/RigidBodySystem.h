// The scene's moving boundary objects (Simulation/MovingBodies.h): dynamic rigid bodies (two-way
// coupled with the fluid, paper Section 3.5, Eq. (35)), animated (kinematic) bodies and hinges.
// It gathers the pressure impulses the solver reports per fluid-boundary pair into force and
// torque per body (per-thread accumulators, no atomics), integrates the bodies and gives their
// poses to the boundary model, which moves the samples; those carry the body's velocity into the
// next pressure solve.
#pragma once
#include <limits>
#include <span>
#include <string>
#include <vector>

#include "Boundary/RigidBody.h"
#include "Boundary/RigidContact.h"
#include "Simulation/BoundarySamples.h"
#include "Simulation/MovingBodies.h"
#include "Simulation/NeighborSearch.h"
#include "Simulation/ParticleView.h"
#include "Utilities/Log.h"

namespace consph {

// Revolute joint of one dynamic body about a fixed world axis (reduced coordinates: the body
// keeps exactly one rotational degree of freedom, so the axle point stays fixed to round-off).
struct Hinge {
  Index body = 0;
  HingeDescription description;
};

class RigidBodySystem final : public MovingBodies {
 public:
  // Builds a body for every non-static object; `samples` are the boundary model's samples of
  // all objects (sample k belongs to object samples.bodies[k]).
  // `layerDepth[o]`: how far object o's samples lie inside its solid (rigid contact);
  // `minContactDistance`: the closest two sample layers may come.
  // `contactSpacing` > 0: the model's samples are no surface layer (volume maps: virtual
  // particles rebuilt every step), so rigid contact works on points sampled on every object's
  // surface this far apart instead (half that inside the solid), owned and moved by this
  // system (contactSurface()).
  RigidBodySystem(const std::vector<BoundaryObject>& objects, const BoundarySamples& samples, std::vector<Real> layerDepth,
                  Real minContactDistance, const LogSink& log, Real contactSpacing = 0);

  bool empty() const { return bodies_.empty(); }
  std::size_t dynamicCount() const override { return dynamicCount_; }
  std::size_t count() const override { return bodies_.size(); }
  MovingBodyState state(std::size_t body) const override;
  void restoreState(std::size_t body, const MovingBodyState& state) override;
  const std::vector<RigidBody>& bodies() const { return bodies_; }
  std::vector<RigidBody>& bodies() { return bodies_; }

  // Sums the impulse the fluid gave each sample of a moving body (pairImpulses[e] for the pair
  // e = (i, k) of `lists`) into impulse and angular impulse per body, the torque taken at the
  // fluid particle x_i (fluid plus bodies then conserve angular momentum whatever the pair
  // force's direction).
  void takeFluidImpulses(const NeighborLists& lists, const std::vector<Vector3r>& fluidPositions,
                         const BoundarySamples& samples, const std::vector<Vector3r>& pairImpulses) override;
  // One step: dynamic bodies take the gathered impulses and gravity (hinged ones about their
  // axle, with the motor), free ones then rigid contact (RigidContact, on the current
  // `samples`), animated ones follow their prescribed velocity. Clears the impulses.
  // A light free body (Boundary/AddedMass.h) shares its impulses with the fluid touching it
  // (found by takeFluidImpulses): their velocities change too.
  void advance(Real dt, const Vector3r& gravity, const BoundarySamples& samples, const std::vector<Vector3r>& fluidPositions,
               const std::vector<Real>& fluidMasses, std::vector<Vector3r>& fluidVelocities) override;
  // The fluid's rest density: from it each free body's added mass (AddedMass.h; 0 for a body
  // at least kAddedMassCoefficient times as dense as the fluid).
  void setFluidDensity(Real rho0);
  // Object pairs whose sample layers overlap by more than `tolerance` m now, one of them a free
  // dynamic body (a start-up check: bodies drawn into each other or into a wall).
  std::vector<BodyOverlap> overlaps(const BoundarySamples& samples, Real tolerance) override;
  Real maxPushOutSpeed() const override { return RigidContact::kMaxPushOutSpeed; }
  // Contacts found in the last advance().
  std::size_t contactCount() const { return contactCount_; }
  // The points rigid contact works on: the model's `samples`, or this system's own surface
  // points when it was built with a contact spacing.
  const BoundarySamples& contactSurface(const BoundarySamples& samples) const {
    return ownContactSurface_ ? contactPoints_ : samples;
  }
  // Each moving object's pose for the boundary model (BoundaryModel::follow moves the samples,
  // an implicit model its maps). `onlyChanged`: skip the bodies whose state is the one given last
  // time (an animated body at rest costs nothing per step).
  const std::vector<PoseUpdate>& poses(bool onlyChanged) override;

  // BodyResponse: the free dynamic bodies' samples move as if the bodies took the impulses so far.
  const std::vector<MovingPair>& movingPairs(const NeighborLists& lists, std::span<const Vector3r> fluidPositions,
                                             std::span<const Real> fluidMasses, const BoundaryView& samples) override;
  void respond(std::span<const Vector3r> fluidPositions, const std::vector<Vector3r>& impulses, const Vector3r& gravity, Real dt,
               const BoundaryView& samples) override;
  void restore(const BoundaryView& samples) override;
  bool hasFreeDynamic() const override;

  // Linear momentum of the dynamic bodies, kg m/s.
  Vector3r momentum() const;

  // Output: one CSV row per body (header first), and the bodies' surfaces as one .vtu.
  std::string csvHeader() const override;
  std::string csvRows(double time) const override;
  std::string meshesToVtu() const;
  // Every body's surface where it is now: one mesh, each vertex's body (object index) and velocity.
  void worldMeshes(TriangleMesh& mesh, std::vector<Index>& body, std::vector<Vector3r>& velocity) const override;

 private:
  // Free dynamic bodies: not hinged (rigid contact moves these only); fixed at construction.
  std::vector<char> free_;
  void advanceHinged(RigidBody& b, const HingeDescription& h, const Vector3r& J, const Vector3r& L, Real dt);
  // How far own contact points lie inside their solid: half their spacing, so that two faces
  // in touch hold their layers one spacing apart.
  static Real contactLayerDepth(Real spacing) { return Real(0.5) * spacing; }
  // Samples every object's surface into contactPoints_ (moving bodies' points also in the body frame).
  void sampleContactSurface(const std::vector<BoundaryObject>& objects, Real spacing, const LogSink& log);
  // The own contact points of the moving bodies where the bodies are now.
  void moveContactPoints();

  std::vector<RigidBody> bodies_;
  std::vector<Index> hingeOfBody_;   // index into hinges_, or kNone
  std::vector<Hinge> hinges_;
  std::vector<Index> bodyOfObject_;  // object index -> body index, or kNone
  std::size_t dynamicCount_ = 0;
  RigidContact contact_;
  bool ownContactSurface_ = false;
  BoundarySamples contactPoints_;  // the own contact surface (contactSpacing > 0)
  std::size_t contactCount_ = 0;
  // Per-thread accumulators (threads x bodies x {impulse, angular impulse}), then their sum.
  std::vector<Vector3r> perThread_;
  std::vector<Vector3r> impulse_, angularImpulse_;
  std::vector<Vector3r> trialImpulse_, trialAngularImpulse_;  // respond()'s sums
  std::vector<Vector3r> trialVelocity_, trialAngularVelocity_;
  // This step's moving pairs, their sample's body, and the fluid touching each body (respond's
  // added mass); the step they are for.
  std::vector<MovingPair> movingPairs_;
  std::vector<Index> movingPairBody_;
  std::vector<Real> touchingMass_;
  std::vector<Real> addedMass_;                // per body, kg (setFluidDensity)
  std::vector<std::vector<Index>> touching_;   // this step's fluid touching each light body
  std::vector<Matrix3r> touchingInertia_;
  std::size_t movingPairsStep_ = ~std::size_t(0), stepsAdvanced_ = 0;
  // Each body's state as poses() last gave it, and the poses of that call.
  struct WrittenState {  // NaN until written: unequal to any state
    Vector3r x = Vector3r::Constant(std::numeric_limits<Real>::quiet_NaN()), v = x, w = x;
    Quaternionr q = Quaternionr(x[0], x[0], x[0], x[0]);
  };
  std::vector<WrittenState> written_;
  std::vector<PoseUpdate> poses_;
  // Calls f(k, body) for every sample k of a free dynamic body.
  template <class Samples, class F>  // a BoundaryView today; only its bodies are read
  void forEachFreeSample(const Samples& samples, F&& f) const;
  static constexpr Index kNone = ~Index(0);
};

}  // namespace consph
