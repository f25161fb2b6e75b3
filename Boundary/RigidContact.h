// Simple rigid contact: dynamic bodies against static objects, animated or hinged bodies and
// each other, through points on their surfaces (RigidBody::contactSamples: the boundary samples
// of particle walls, or points sampled for contact alone with volume maps). Velocity level, solved before the bodies move: for
// every sample of a free dynamic body near a sample of another object, the relative normal
// velocity may close at most the remaining gap this step and pushes apart at a bounded rate when
// the layers already overlap (sequential impulses, accumulated and clamped non-negative, so
// contacts only push); Coulomb friction opposes the tangential velocity with an accumulated
// impulse kept inside the cone |J_t| <= mu J_n (mu = sqrt(mu_a mu_b) of the two objects'
// "friction"). Enough that a body that sinks rests on the floor instead of passing through it
// and a sliding one stops; not a general rigid-body solver (no stacking guarantees).
#pragma once
#include <vector>

#include "Boundary/RigidBody.h"
#include "Simulation/BoundarySamples.h"
#include "Simulation/NeighborSearch.h"

namespace consph {

class RigidContact {
 public:
  // `layerDepth[o]`: how far object o's samples lie inside its solid; two objects touch when
  // their sample layers are layerDepth[a] + layerDepth[b] apart (at least `minDistance`).
  // `friction[o]`: object o's Coulomb coefficient.
  RigidContact(std::vector<Real> layerDepth, std::vector<Real> friction, Real minDistance)
      : layerDepth_(std::move(layerDepth)), friction_(std::move(friction)), minDistance_(minDistance) {}

  // Changes the velocities of the bodies with solvable[b] (free dynamic bodies); every other
  // body is an obstacle moving with its own velocity. `bodyOfObject[o]`: o's body or kNone.
  // Returns the number of contacts this step.
  std::size_t solve(std::vector<RigidBody>& bodies, const std::vector<char>& solvable, const std::vector<Index>& bodyOfObject,
                    const BoundarySamples& samples, Real dt);

  // The object pairs (sample-layer owners, objectA < objectB) whose layers overlap by more than
  // `tolerance`, with the deepest overlap of each, m: a start-up check (bodies drawn into each
  // other or into a wall); nothing is changed.
  struct Overlap {
    Index objectA, objectB;
    Real depth;
  };
  std::vector<Overlap> overlaps(const std::vector<RigidBody>& bodies, const std::vector<char>& solvable,
                                const std::vector<Index>& bodyOfObject, const BoundarySamples& samples, Real tolerance);

  static constexpr Index kNone = ~Index(0);
  static constexpr int kIterations = 10;
  static constexpr Real kPushOutRate = Real(0.2);  // fraction of an overlap removed per step
  // m/s, the fastest an overlap is pushed apart: the fluid's default DFSPH overlapReliefSpeed.
  // Without it two boxes drawn 5 cm into each other separated at 0.2 x 5 cm / 1 ms = 10 m/s.
  static constexpr Real kMaxPushOutSpeed = Real(0.25);

 private:
  struct Contact {
    Index body, other;  // other: a body index or kNone (static)
    Index k, l;         // the two samples
    Vector3r normal;    // from l to k
    Real gap;           // distance minus contact distance (negative: overlap)
    Real friction;      // Coulomb coefficient of the pair
    Real impulse = 0;   // accumulated normal impulse
    Vector3r tangentImpulse = Vector3r::Zero();  // accumulated friction impulse
  };
  class ImpulseSolver;  // the sequential-impulse sweeps over one step's contacts (RigidContact.cpp)
  // Contacts of the bodies with solvable[b]: their samples within reach of another object.
  std::vector<Contact> findContacts(const std::vector<RigidBody>& bodies, const std::vector<char>& solvable,
                                    const std::vector<Index>& bodyOfObject, const BoundarySamples& samples);
  // Calls f(l, x_l) for every sample l within `radius` of p: static samples from a grid built
  // once (they never move), moving ones from a grid rebuilt every step.
  // `withMoving`: false when no other moving body is near (skips the body's own samples).
  template <class F>
  void forEachSampleNear(const Vector3r& p, Real radius, bool withMoving, F&& f) const {
    staticGrid_.forEachNeighbor(p, radius, [&](Index j, const Vector3r& x) { f(staticIndex_[j], x); });
    if (withMoving) movingGrid_.forEachNeighbor(p, radius, [&](Index j, const Vector3r& x) { f(movingIndex_[j], x); });
  }

  std::vector<Real> layerDepth_, friction_;
  Real minDistance_;
  bool staticBuilt_ = false;
  PointGrid staticGrid_, movingGrid_;
  std::vector<Vector3r> staticPoints_, movingPoints_;
  std::vector<Index> staticIndex_, movingIndex_;  // grid entry -> sample
  std::vector<std::vector<Contact>> perThread_;
};

}  // namespace consph
