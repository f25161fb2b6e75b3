// Interface of boundary models (particle boundaries after Akinci 2012, volume maps, ...).
// A model turns the scene's boundary objects into BoundarySamples and finds, every step, the
// samples near each fluid particle. Solvers and forces see only those samples.
#pragma once
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "Simulation/BoundarySamples.h"
#include "Simulation/FluidModel.h"
#include "Simulation/NeighborSearch.h"
#include "Simulation/ResourceEstimate.h"
#include "Utilities/AxisAlignedBox.h"
#include "Utilities/TriangleMesh.h"

namespace consph {

// How a boundary object moves (docs/rigid-bodies.md).
enum class BodyMotion {
  Static,    // never moves
  Dynamic,   // a rigid body moved by gravity and the fluid (two-way coupled, paper Section 3.5)
  Animated   // kinematic: moves with a prescribed velocity, pushes the fluid, feels nothing
};

// A revolute joint about a fixed world axis through a fixed point, with an optional motor.
struct HingeDescription {
  bool enabled = false;
  Vector3r point = Vector3r::Zero();          // m, a point on the axle
  Vector3r axis = Vector3r::UnitZ();          // unit axis direction
  bool motor = false;
  Real targetVelocity = 0;                    // rad/s about axis
  Real maxTorque = 0;                         // N m
};

// One boundary object of the scene, its geometry already in world space.
struct BoundaryObject {
  std::string name;
  std::string path;  // JSON path, for messages
  TriangleMesh mesh;
  bool isBox = false;  // an axis-aligned box [boxMin, boxMax]: sampled on regular face grids
  Vector3r boxMin = Vector3r::Zero(), boxMax = Vector3r::Zero();
  bool inverted = false;  // the fluid is inside (a container)

  BodyMotion motion = BodyMotion::Static;
  Real density = 0;  // kg/m^3 (dynamic bodies): mass and inertia follow from the closed mesh
  // Dynamic: initial velocities; animated: the prescribed ones. About the centre of mass.
  Vector3r velocity = Vector3r::Zero();         // m/s
  Vector3r angularVelocity = Vector3r::Zero();  // rad/s
  HingeDescription hinge;                       // dynamic bodies only
  Real friction = Real(0.5);  // Coulomb coefficient in rigid contact; a pair uses sqrt(mu_a mu_b)

  // Settings of this object's volume map (implicit boundary models only; Akinci samples ignore
  // them with a warning). 0: the model's cell size.
  Real mapCellSize = 0;   // in particle radii r
  Real mapThickness = 0;  // m: the surface moved this far into the fluid (SPlisHSPlasH's mapThickness)
};

// Where a moving object is now: the point p it had at t = 0 is at centre + rotation (p -
// initialCentre), moving with velocity + angularVelocity x (. - centre).
struct ObjectPose {
  Matrix3r rotation = Matrix3r::Identity();
  Vector3r centre = Vector3r::Zero(), initialCentre = Vector3r::Zero();
  Vector3r velocity = Vector3r::Zero(), angularVelocity = Vector3r::Zero();

  // Where the world point x was at t = 0, seen from the object.
  Vector3r toInitial(const Vector3r& x) const { return initialCentre + rotation.transpose() * (x - centre); }
  Vector3r velocityAt(const Vector3r& x) const { return velocity + angularVelocity.cross(x - centre); }
};

// A moving object's pose for the boundary model (MovingBodies::poses); `moved`: its position or
// orientation changed (false: only its velocities), so the model's neighbour structure is stale.
struct PoseUpdate {
  std::size_t object = 0;
  ObjectPose pose;
  bool moved = true;
};

class BoundaryModel {
 public:
  virtual ~BoundaryModel() = default;
  // `fluid` holds the initial particles (after the blocks are sampled): a model may place its
  // samples where that fluid can rest (the Akinci model's "auto" surface offset).
  virtual void initialize(const std::vector<BoundaryObject>& objects, const FluidModel& fluid, const CubicSplineKernel& kernel) = 0;
  // What initialize() would allocate for `objects`, computed in floating point before it runs,
  // so that a scene too large to fit is refused up front (ResourceEstimate).
  virtual BoundaryEstimate estimate(const std::vector<BoundaryObject>& objects, const CubicSplineKernel& kernel) const = 0;
  // Fills fluid i -> boundary sample k lists (with cached kernel gradients). `fluidDensities`
  // (null, or one per fluid particle: its fluid density sum_j m_j W_ij, m_i W(0) included): a
  // model whose search can sum its samples' m~_k W_ik while it lists them fills out.kernelSums
  // with fluidDensities[i] plus that sum, added in list order (the particle's density, the bits
  // of a loop over its lists after the fluid's); otherwise out.kernelSums is left empty.
  virtual void findNeighbors(const FluidModel& fluid, const CubicSplineKernel& kernel, NeighborLists& out,
                             const Real* fluidDensities) = 0;
  // True when the samples are virtual particles rebuilt every step (one per fluid particle and
  // object, volume maps), not a fixed sampling of the surfaces.
  virtual bool implicit() const { return false; }
  // The longest step the boundary allows the particles as they move now (the time step takes it
  // like the CFL condition); infinity: no limit (VolumeMap's approachTolerance). `neighbors`: the
  // lists this step's findNeighbors filled, for the particles where they are now. Where the limit
  // is `longestUseful` or more (the step the other bounds give), any value from there up may be
  // returned: a model may skip the particles that cannot shorten the step.
  virtual Real approachStepLimit(const FluidModel& fluid, const NeighborLists& neighbors, const CubicSplineKernel& kernel,
                                 Real longestUseful) const {
    return std::numeric_limits<Real>::infinity();
  }
  // How far object o's samples lie inside its solid (0: on its surface); rigid contact uses it.
  virtual Real layerDepth(std::size_t object) const { return 0; }
  // The moving objects' poses after the bodies moved (every step, and once at start-up): the
  // model is the only writer of its samples' positions. A sampled object's samples go to the
  // pose applied to where they were when it was first given one (t = 0), with the pose's
  // velocity there; an implicit model moves what it keeps per object (onPose). Marks the model
  // moved when an object's position or orientation changed.
  void follow(const std::vector<PoseUpdate>& poses);
  // The part of the impulse J that fluid particle x gave sample k which acts on the part of k's
  // object inside the box [lo, hi] (a force probe's region). Sampled models: all of it where
  // the sample lies in the box, none elsewhere. Volume maps split a virtual particle's load
  // over the surface it stands for.
  virtual Vector3r impulseInBox(Index k, const Vector3r& x, const Vector3r& impulse, const Vector3r& lo, const Vector3r& hi) const {
    return insideBox(samples_.positions[k], lo, hi) ? impulse : Vector3r::Zero();
  }
  // Samples moved (a moving body): the model must rebuild its acceleration structure.
  void markMoved() { moved_ = true; }
  BoundarySamples& samples() { return samples_; }
  const BoundarySamples& samples() const { return samples_; }

 protected:
  // An object's new pose, for what a model keeps per object besides its samples (volume maps).
  virtual void onPose(std::size_t object, const ObjectPose& pose) {}
  BoundarySamples samples_;
  bool moved_ = true;

 private:
  // Per object given a pose: its samples and their positions at t = 0 (kept on first follow()).
  struct ObjectSamples {
    bool known = false;  // given a pose before (its samples below are then collected)
    std::vector<Index> samples;
    std::vector<Vector3r> initialPositions;
  };
  std::vector<ObjectSamples> objectSamples_;
};

}  // namespace consph
