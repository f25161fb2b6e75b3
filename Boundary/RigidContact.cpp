#include "Boundary/RigidContact.h"

#include <algorithm>
#include <limits>
#include <tuple>

#include "Utilities/ParallelFor.h"

namespace consph {

std::vector<RigidContact::Contact> RigidContact::findContacts(const std::vector<RigidBody>& bodies,
                                                              const std::vector<char>& solvable,
                                                              const std::vector<Index>& bodyOfObject,
                                                              const BoundarySamples& samples) {
  // Only free bodies with contact points can touch anything.
  bool any = false;
  for (std::size_t b = 0; b < bodies.size(); ++b) any |= solvable[b] && !bodies[b].contactSamples.empty();
  if (!any) return {};
  const Real maxDepth = *std::max_element(layerDepth_.begin(), layerDepth_.end());
  const Real reach = std::max(2 * maxDepth, minDistance_);
  // Contacts are looked for a little beyond touching, so a body closing in fast is caught the
  // step before it would overlap (speculative contacts: the gap may close, not more).
  const Real margin = minDistance_;
  const Real cell = reach + margin;
  if (!staticBuilt_) {
    for (std::size_t k = 0; k < samples.size(); ++k)
      if (bodyOfObject[samples.bodies[k]] == kNone) {
        staticPoints_.push_back(samples.positions[k]);
        staticIndex_.push_back(Index(k));
      }
    staticGrid_.build(staticPoints_.data(), staticPoints_.size(), cell);
    staticBuilt_ = true;
  }
  movingPoints_.clear();
  movingIndex_.clear();
  for (const RigidBody& body : bodies)
    for (Index k : body.contactSamples) {
      movingPoints_.push_back(samples.positions[k]);
      movingIndex_.push_back(k);
    }
  movingGrid_.build(movingPoints_.data(), movingPoints_.size(), cell);
  // Broad phase between moving bodies: their samples' bounding boxes, grown by the reach.
  std::vector<Vector3r> lo(bodies.size(), Vector3r::Constant(std::numeric_limits<Real>::max())),
      hi(bodies.size(), Vector3r::Constant(std::numeric_limits<Real>::lowest()));
  for (std::size_t b = 0; b < bodies.size(); ++b)
    for (Index k : bodies[b].contactSamples) {
      lo[b] = lo[b].cwiseMin(samples.positions[k]);
      hi[b] = hi[b].cwiseMax(samples.positions[k]);
    }
  auto nearOtherBody = [&](std::size_t b) {
    for (std::size_t c = 0; c < bodies.size(); ++c)
      if (c != b && (lo[c] - hi[b]).maxCoeff() < cell && (lo[b] - hi[c]).maxCoeff() < cell) return true;
    return false;
  };

  perThread_.assign(parallelChunkCount(), {});
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    if (!solvable[b]) continue;
    const RigidBody& body = bodies[b];
    const Index object = body.object;
    const bool withMoving = nearOtherBody(b);
    // Each chunk appends to its own list across all bodies, and the lists are concatenated in
    // chunk order (the order the solver sees).
    parallelChunks(body.contactSamples.size(), [&](std::size_t chunk, std::size_t begin, std::size_t end) {
      for (std::size_t s = begin; s < end; ++s) {
        const Index k = body.contactSamples[s];
        const Vector3r xk = samples.positions[k];
        // The closest other object, then its surface near x_k from the weighted mean and spread
        // of its samples there: a sample-to-sample direction would tilt wherever the two sample
        // grids do not line up and push the bodies sideways.
        Index closestObject = kNone, closestSample = kNone;
        Real closest = std::numeric_limits<Real>::max();
        forEachSampleNear(xk, cell, withMoving, [&](Index l, const Vector3r& xl) {
          if (samples.bodies[l] == object) return;
          const Real distance = (xk - xl).norm();
          if (distance < closest) {
            closest = distance;
            closestObject = samples.bodies[l];
            closestSample = l;
          }
        });
        if (closestObject == kNone) continue;
        const Real radius = cell;
        Vector3r direction = Vector3r::Zero(), mean = Vector3r::Zero();
        Real weightSum = 0;
        forEachSampleNear(xk, radius, withMoving, [&](Index l, const Vector3r& xl) {
          if (samples.bodies[l] != closestObject) return;
          const Real q = 1 - (xk - xl).norm() / radius, w = q * q;
          direction += w * (xk - xl);
          mean += w * xl;
          weightSum += w;
        });
        if (weightSum <= 0 || direction.norm() <= 0) continue;
        const Vector3r normal = direction.normalized();
        const Real gap = (xk - mean / weightSum).dot(normal) - std::max(layerDepth_[object] + layerDepth_[closestObject], minDistance_);
        if (gap < margin)
          perThread_[chunk].push_back(
              {Index(b), bodyOfObject[closestObject], k, closestSample, normal, gap, std::sqrt(friction_[object] * friction_[closestObject])});
      }
    });
  }
  std::vector<Contact> contacts;
  for (auto& list : perThread_) contacts.insert(contacts.end(), list.begin(), list.end());
  return contacts;
}

std::vector<RigidContact::Overlap> RigidContact::overlaps(const std::vector<RigidBody>& bodies, const std::vector<char>& solvable,
                                                          const std::vector<Index>& bodyOfObject, const BoundarySamples& samples,
                                                          Real tolerance) {
  // The deepest overlap per pair of objects, the pair ordered so that each is reported once.
  std::vector<Overlap> found;
  for (const Contact& c : findContacts(bodies, solvable, bodyOfObject, samples)) {
    if (-c.gap <= tolerance) continue;
    Index a = samples.bodies[c.k], b = samples.bodies[c.l];
    if (a > b) std::swap(a, b);
    auto it = std::find_if(found.begin(), found.end(), [&](const Overlap& o) { return o.objectA == a && o.objectB == b; });
    if (it == found.end()) found.push_back({a, b, -c.gap});
    else it->depth = std::max(it->depth, -c.gap);
  }
  std::sort(found.begin(), found.end(),
            [](const Overlap& x, const Overlap& y) { return std::tie(x.objectA, x.objectB) < std::tie(y.objectA, y.objectB); });
  return found;
}

// The velocities, impulses and effective masses one step's contacts are solved with: the
// bodies' world inverse inertias taken once, before the sweeps change their velocities.
class RigidContact::ImpulseSolver {
 public:
  ImpulseSolver(std::vector<RigidBody>& bodies, const std::vector<char>& solvable, const BoundarySamples& samples, Real dt)
      : bodies_(bodies), solvable_(solvable), samples_(samples), dt_(dt), invInertia_(bodies.size()) {
    for (std::size_t b = 0; b < bodies.size(); ++b) invInertia_[b] = bodies[b].invInertiaWorld();
  }

  // Normal impulse: the closing speed allowed is the gap left (>= 0), or a bounded push-out speed
  // once overlapping: a fraction of the overlap per step, and never faster than kMaxPushOutSpeed,
  // so a deep overlap (bodies drawn into each other) comes apart gently instead of at overlap / dt.
  void solveNormal(Contact& c) {
    const Real target = c.gap >= 0 ? -c.gap / dt_ : std::min(-kPushOutRate * c.gap / dt_, kMaxPushOutSpeed);
    const Real updated =
        std::max(c.impulse + (target - relativeVelocity(c).dot(c.normal)) / inverseMassAlong(c, c.normal), Real(0));
    const Real delta = updated - c.impulse;
    c.impulse = updated;
    if (delta != 0) applyImpulse(c, delta * c.normal);
  }

  // Friction: the impulse that stops the tangential slip, then back into the Coulomb cone.
  void solveFriction(Contact& c) {
    if (c.friction <= 0 || (c.impulse == 0 && c.tangentImpulse == Vector3r::Zero())) return;
    const Vector3r now = relativeVelocity(c);
    const Vector3r slip = now - now.dot(c.normal) * c.normal;
    const Real slipSpeed = slip.norm();
    Vector3r tangentImpulse = c.tangentImpulse;
    if (slipSpeed > 0) {
      const Vector3r t = slip / slipSpeed;
      tangentImpulse -= (slipSpeed / inverseMassAlong(c, t)) * t;
    }
    const Real limit = c.friction * c.impulse, magnitude = tangentImpulse.norm();
    if (magnitude > limit) tangentImpulse *= limit / magnitude;
    const Vector3r change = tangentImpulse - c.tangentImpulse;
    c.tangentImpulse = tangentImpulse;
    if (change != Vector3r::Zero()) applyImpulse(c, change);
  }

 private:
  bool freeOther(const Contact& c) const { return c.other != kNone && solvable_[c.other]; }
  Vector3r velocityAt(Index body, Index sample) const {
    if (body == kNone) return samples_.velocities[sample];  // static: zero; kinematic: its own
    return bodies_[body].velocityAt(samples_.positions[sample]);
  }
  // Velocity of body a at sample k relative to the other object at sample l.
  Vector3r relativeVelocity(const Contact& c) const {
    return bodies_[c.body].velocityAt(samples_.positions[c.k]) - velocityAt(c.other, c.l);
  }
  // An impulse J on body a at sample k (and -J on the other body at sample l, when it is free).
  void applyImpulse(const Contact& c, const Vector3r& J) {
    RigidBody& a = bodies_[c.body];
    a.v += J / a.mass;
    a.w += invInertia_[c.body] * (samples_.positions[c.k] - a.x).cross(J);
    if (freeOther(c)) {
      RigidBody& o = bodies_[c.other];
      o.v -= J / o.mass;
      o.w -= invInertia_[c.other] * (samples_.positions[c.l] - o.x).cross(J);
    }
  }
  // The change of the relative velocity along unit d per unit impulse along d.
  Real inverseMassAlong(const Contact& c, const Vector3r& d) const {
    const RigidBody& a = bodies_[c.body];
    const Vector3r raXd = (samples_.positions[c.k] - a.x).cross(d);
    Real inverse = 1 / a.mass + raXd.dot(invInertia_[c.body] * raXd);
    if (freeOther(c)) {
      const RigidBody& o = bodies_[c.other];
      const Vector3r rbXd = (samples_.positions[c.l] - o.x).cross(d);
      inverse += 1 / o.mass + rbXd.dot(invInertia_[c.other] * rbXd);
    }
    return inverse;
  }

  std::vector<RigidBody>& bodies_;
  const std::vector<char>& solvable_;
  const BoundarySamples& samples_;
  const Real dt_;
  std::vector<Matrix3r> invInertia_;
};

std::size_t RigidContact::solve(std::vector<RigidBody>& bodies, const std::vector<char>& solvable,
                                const std::vector<Index>& bodyOfObject, const BoundarySamples& samples, Real dt) {
  std::vector<Contact> contacts = findContacts(bodies, solvable, bodyOfObject, samples);
  if (contacts.empty()) return 0;
  ImpulseSolver solver(bodies, solvable, samples, dt);
  for (int it = 0; it < kIterations; ++it)
    for (Contact& c : contacts) {
      solver.solveNormal(c);
      solver.solveFriction(c);
    }
  return contacts.size();
}

}  // namespace consph
