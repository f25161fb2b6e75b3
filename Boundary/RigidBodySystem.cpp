#include "Boundary/RigidBodySystem.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "Boundary/AddedMass.h"
#include "Boundary/ObjectSampling.h"
#include "Utilities/Error.h"
#include "Utilities/MassProperties.h"
#include "Utilities/ParallelFor.h"
#include "Utilities/VtkWriter.h"

namespace consph {

namespace {
std::vector<Real> frictionOf(const std::vector<BoundaryObject>& objects) {
  std::vector<Real> friction;
  for (const BoundaryObject& o : objects) friction.push_back(o.friction);
  return friction;
}
}  // namespace

RigidBodySystem::RigidBodySystem(const std::vector<BoundaryObject>& objects, const BoundarySamples& samples,
                                 std::vector<Real> layerDepth, Real minContactDistance, const LogSink& log,
                                 Real contactSpacing)
    : contact_(contactSpacing > 0 ? std::vector<Real>(layerDepth.size(), contactLayerDepth(contactSpacing)) : std::move(layerDepth),
               frictionOf(objects), minContactDistance) {
  bodyOfObject_.assign(objects.size(), kNone);
  for (std::size_t o = 0; o < objects.size(); ++o) {
    const BoundaryObject& obj = objects[o];
    if (obj.motion == BodyMotion::Static) continue;
    RigidBody b;
    b.name = obj.name.empty() ? obj.path : obj.name;
    b.motion = obj.motion;
    b.object = Index(o);
    const MassProperties mp = computeMassProperties(obj.mesh);
    if (obj.motion == BodyMotion::Dynamic) {
      if (!(mp.volume > 0))
        throw InputError(obj.path + ": a dynamic body needs a closed mesh with outward-facing triangles (its volume is " +
                         std::to_string(mp.volume) + " m^3)");
      b.mass = obj.density * mp.volume;
      b.volume = mp.volume;
      b.inertiaBody = obj.density * mp.inertiaPerDensity;
      b.invInertiaBody = b.inertiaBody.inverse();
      b.x = mp.centerOfMass;
      ++dynamicCount_;
    } else {
      // Animated: rotates about its centre of volume, or about its vertices' centroid when open.
      Vector3r c = Vector3r::Zero();
      for (auto& v : obj.mesh.vertices) c += v;
      b.x = mp.volume > 0 ? mp.centerOfMass : Vector3r(c / Real(std::max<std::size_t>(obj.mesh.vertices.size(), 1)));
    }
    b.x0 = b.x;
    b.v = obj.velocity;
    b.w = obj.angularVelocity;
    b.localMesh = obj.mesh;
    for (auto& v : b.localMesh.vertices) {
      v -= b.x;
      b.reach = std::max(b.reach, v.norm());
    }
    bodyOfObject_[o] = Index(bodies_.size());
    bodies_.push_back(std::move(b));
    if (log && obj.motion == BodyMotion::Dynamic) {
      const RigidBody& nb = bodies_.back();
      std::ostringstream s;
      s << obj.path << ": dynamic body '" << nb.name << "', volume " << mp.volume << " m^3, mass " << nb.mass
        << " kg, centre of mass (" << nb.x[0] << ", " << nb.x[1] << ", " << nb.x[2] << ")";
      log(LogLevel::Info, s.str());
    }
  }
  for (std::size_t k = 0; k < samples.size(); ++k) {
    const Index b = bodyOfObject_[samples.bodies[k]];
    if (b == kNone) continue;
    bodies_[b].samples.push_back(Index(k));
  }
  // Rigid contact only moves free dynamic bodies: without one, no contact surface is needed.
  if (contactSpacing > 0 && dynamicCount_ > 0) sampleContactSurface(objects, contactSpacing, log);
  else
    for (RigidBody& b : bodies_) b.contactSamples = b.samples;
  hingeOfBody_.assign(bodies_.size(), kNone);
  for (std::size_t o = 0; o < objects.size(); ++o) {
    if (!objects[o].hinge.enabled) continue;
    hingeOfBody_[bodyOfObject_[o]] = Index(hinges_.size());
    hinges_.push_back({bodyOfObject_[o], objects[o].hinge});
    // A hinged body starts rotating about its axle only.
    RigidBody& b = bodies_[bodyOfObject_[o]];
    const Vector3r a = objects[o].hinge.axis;
    b.w = b.w.dot(a) * a;
    b.v = b.w.cross(b.x - objects[o].hinge.point);
  }
  impulse_.assign(bodies_.size(), Vector3r::Zero());
  angularImpulse_.assign(bodies_.size(), Vector3r::Zero());
  free_.assign(bodies_.size(), 0);
  for (std::size_t i = 0; i < bodies_.size(); ++i) free_[i] = bodies_[i].motion == BodyMotion::Dynamic && hingeOfBody_[i] == kNone;
}

void RigidBodySystem::takeFluidImpulses(const NeighborLists& lists, const std::vector<Vector3r>& fluidPositions,
                                          const BoundarySamples& samples, const std::vector<Vector3r>& pairImpulses) {
  const std::size_t nb = bodies_.size(), n = lists.queryCount();
  const std::size_t chunks = parallelChunkCount();
  perThread_.assign(chunks * nb * 2, Vector3r::Zero());
  // Chunks, not parallelReduce: the per-chunk sums live in a buffer kept between steps (no
  // allocation per call), and are added to the running totals chunk by chunk, in this order.
  parallelChunks(n, [&](std::size_t chunk, std::size_t begin, std::size_t end) {
    Vector3r* acc = perThread_.data() + chunk * nb * 2;
    for (std::size_t i = begin; i < end; ++i)
      for (Index e = lists.begin(i); e < lists.end(i); ++e) {
        const Index k = lists.indices[e];
        const Index b = bodyOfObject_[samples.bodies[k]];
        if (b == kNone) continue;
        const Vector3r& J = pairImpulses[e];
        acc[2 * b] += J;
        // The torque of the reaction about x, taken at the fluid particle: the fluid's angular
        // momentum changes by x_i x (-J), so the total is conserved whatever the pair's force
        // direction (a volume map's has a grad V part off x_i - x_k; an Akinci pair's lies
        // along it, where x_i and x_k give the same torque).
        acc[2 * b + 1] += (fluidPositions[i] - bodies_[b].x).cross(J);
      }
  });
  for (std::size_t t = 0; t < chunks; ++t)
    for (std::size_t b = 0; b < nb; ++b) {
      impulse_[b] += perThread_[(t * nb + b) * 2];
      angularImpulse_[b] += perThread_[(t * nb + b) * 2 + 1];
    }
  // The fluid touching each light body (advance() lends it to the body), each particle once.
  // Serial, and only with a light body in the scene.
  touching_.resize(nb);
  for (auto& t : touching_) t.clear();
  if (std::none_of(addedMass_.begin(), addedMass_.end(), [](Real m) { return m > 0; })) return;
  for (std::size_t i = 0; i < n; ++i)
    for (Index e = lists.begin(i); e < lists.end(i); ++e) {
      const Index b = bodyOfObject_[samples.bodies[lists.indices[e]]];
      if (b == kNone || !(addedMass_[b] > 0)) continue;
      if (touching_[b].empty() || touching_[b].back() != Index(i)) touching_[b].push_back(Index(i));
    }
}

void RigidBodySystem::setFluidDensity(Real rho0) {
  addedMass_.assign(bodies_.size(), Real(0));
  for (std::size_t i = 0; i < bodies_.size(); ++i)
    if (free_[i]) addedMass_[i] = std::max(Real(0), kAddedMassCoefficient * rho0 * bodies_[i].volume - bodies_[i].mass);
}

bool RigidBodySystem::hasFreeDynamic() const { return std::find(free_.begin(), free_.end(), 1) != free_.end(); }

const std::vector<MovingPair>& RigidBodySystem::movingPairs(const NeighborLists& lists, std::span<const Vector3r> fluidPositions,
                                                            std::span<const Real> fluidMasses, const BoundaryView& samples) {
  // Once per step: the neighbour lists are fixed until the bodies move (advance()).
  if (movingPairsStep_ == stepsAdvanced_) return movingPairs_;
  movingPairsStep_ = stepsAdvanced_;
  const std::size_t nb = bodies_.size();
  movingPairs_.clear();
  movingPairBody_.clear();
  touchingMass_.assign(nb, Real(0));
  touchingInertia_.assign(nb, Matrix3r::Zero());
  // Serial: a body's pairs are a small share of all (the walls' are skipped at one test each).
  std::vector<std::size_t> lastParticle(nb, ~std::size_t(0));
  for (std::size_t i = 0; i < lists.queryCount(); ++i)
    for (Index e = lists.begin(i); e < lists.end(i); ++e) {
      const Index b = bodyOfObject_[samples.bodies[lists.indices[e]]];
      if (b == kNone || !free_[b]) continue;
      movingPairs_.push_back({Index(i), e});
      movingPairBody_.push_back(b);
      if (lastParticle[b] == i) continue;  // each touching particle once per body
      lastParticle[b] = i;
      const Vector3r r = fluidPositions[i] - bodies_[b].x;
      touchingMass_[b] += fluidMasses[i];
      touchingInertia_[b] += fluidMasses[i] * (r.squaredNorm() * Matrix3r::Identity() - r * r.transpose());
    }
  return movingPairs_;
}

void RigidBodySystem::respond(std::span<const Vector3r> fluidPositions, const std::vector<Vector3r>& impulses,
                              const Vector3r& gravity, Real dt, const BoundaryView& samples) {
  trialImpulse_.assign(bodies_.size(), Vector3r::Zero());
  trialAngularImpulse_.assign(bodies_.size(), Vector3r::Zero());
  // As takeFluidImpulses: the torque taken at the fluid particle.
  for (std::size_t p = 0; p < movingPairs_.size(); ++p) {
    const Index b = movingPairBody_[p];
    trialImpulse_[b] += impulses[p];
    trialAngularImpulse_[b] += (fluidPositions[movingPairs_[p].fluid] - bodies_[b].x).cross(impulses[p]);
  }
  // Free dynamic bodies only: hinged ones keep their joint (advanceHinged), animated ones
  // their prescribed motion. Gravity counts: the fluid's support of a resting body's weight
  // leaves it at rest, not rising.
  trialVelocity_.assign(bodies_.size(), Vector3r::Zero());
  trialAngularVelocity_.assign(bodies_.size(), Vector3r::Zero());
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    if (!free_[i]) continue;
    const RigidBody& b = bodies_[i];
    const Matrix3r R = b.rotation();
    trialVelocity_[i] = b.v + (trialImpulse_[i] + dt * b.mass * gravity) / (b.mass + touchingMass_[i]);
    trialAngularVelocity_[i] = b.w + (R * b.inertiaBody * R.transpose() + touchingInertia_[i]).inverse() * trialAngularImpulse_[i];
  }
  forEachFreeSample(samples, [&](Index k, std::size_t i) {
    samples.velocities[k] = trialVelocity_[i] + trialAngularVelocity_[i].cross(samples.positions[k] - bodies_[i].x);
  });
}

void RigidBodySystem::restore(const BoundaryView& samples) {
  forEachFreeSample(samples, [&](Index k, std::size_t i) { samples.velocities[k] = bodies_[i].velocityAt(samples.positions[k]); });
}

template <class Samples, class F>
void RigidBodySystem::forEachFreeSample(const Samples& samples, F&& f) const {
  // A sampled model lists each body's samples; an implicit one (volume maps) makes new virtual
  // samples every step, found by their object.
  bool listed = true;
  for (std::size_t i = 0; i < bodies_.size(); ++i) listed &= !free_[i] || !bodies_[i].samples.empty();
  if (listed) {
    for (std::size_t i = 0; i < bodies_.size(); ++i)
      if (free_[i])
        for (Index k : bodies_[i].samples) f(k, i);
    return;
  }
  for (std::size_t k = 0; k < samples.size(); ++k) {
    const Index i = bodyOfObject_[samples.bodies[k]];
    if (i != kNone && free_[i]) f(Index(k), std::size_t(i));
  }
}

void RigidBodySystem::advance(Real dt, const Vector3r& gravity, const BoundarySamples& samples, const std::vector<Vector3r>& fluidPositions,
                              const std::vector<Real>& fluidMasses, std::vector<Vector3r>& fluidVelocities) {
  // Velocities first (hinged bodies move about their axle at once), then contact on the free
  // dynamic bodies' new velocities, then their positions.
  std::vector<char> free(bodies_.size(), 0);
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    RigidBody& b = bodies_[i];
    b.fluidForce = impulse_[i] / dt;
    b.fluidTorque = angularImpulse_[i] / dt;
    if (b.motion == BodyMotion::Dynamic) {
      const Vector3r J = impulse_[i] + dt * b.mass * gravity;
      if (hingeOfBody_[i] != kNone) advanceHinged(b, hinges_[hingeOfBody_[i]].description, J, angularImpulse_[i], dt);
      else {
        // touching_ is sized by takeFluidImpulses; without it no fluid is known to touch.
        if (i < addedMass_.size() && addedMass_[i] > 0 && i < touching_.size()) {
          const BodyIncrement inc = shareWithTouchingFluid(b, J, angularImpulse_[i], dt, addedMass_[i], touching_[i], fluidPositions,
                                                           fluidMasses, fluidVelocities);
          b.v += inc.dv;
          b.w += inc.dw;
        } else
          b.applyImpulses(J, angularImpulse_[i], dt);
        free[i] = 1;
      }
    }
    impulse_[i].setZero();
    angularImpulse_[i].setZero();
  }
  contactCount_ = contact_.solve(bodies_, free, bodyOfObject_, contactSurface(samples), dt);
  ++stepsAdvanced_;
  for (std::size_t i = 0; i < bodies_.size(); ++i)
    if (free[i] || bodies_[i].motion == BodyMotion::Animated) bodies_[i].advance(dt);  // animated: constant velocities
  moveContactPoints();
}

void RigidBodySystem::sampleContactSurface(const std::vector<BoundaryObject>& objects, Real spacing, const LogSink& log) {
  // The same surface sampling as particle walls, moved kContactLayerDepth into each solid:
  // layers on the surfaces themselves would meet in one plane where two faces touch, and a
  // normal from the other object's points there lies in that plane (measured: a box resting on
  // the floor sank 1 cm and tilted).
  ownContactSurface_ = true;
  for (std::size_t o = 0; o < objects.size(); ++o) {
    const BoundaryObject& obj = objects[o];
    const std::vector<Vector3r> points = sampleObjectSurface(obj, spacing, contactLayerDepth(spacing), log);
    const std::size_t first = contactPoints_.size();
    contactPoints_.resize(first + points.size());
    const Index b = bodyOfObject_[o];
    for (std::size_t s = 0; s < points.size(); ++s) {
      contactPoints_.positions[first + s] = points[s];
      contactPoints_.bodies[first + s] = Index(o);
      if (b == kNone) continue;
      bodies_[b].contactSamples.push_back(Index(first + s));
      bodies_[b].localContactSamples.push_back(points[s] - bodies_[b].x);
    }
  }
  moveContactPoints();
}

void RigidBodySystem::moveContactPoints() {
  if (!ownContactSurface_) return;
  for (const RigidBody& b : bodies_) {
    const Matrix3r R = b.rotation();
    for (std::size_t s = 0; s < b.contactSamples.size(); ++s) {
      const Index k = b.contactSamples[s];
      contactPoints_.positions[k] = b.x + R * b.localContactSamples[s];
      contactPoints_.velocities[k] = b.velocityAt(contactPoints_.positions[k]);
    }
  }
}


std::vector<BodyOverlap> RigidBodySystem::overlaps(const BoundarySamples& samples, Real tolerance) {
  std::vector<BodyOverlap> out;
  for (const RigidContact::Overlap& o : contact_.overlaps(bodies_, free_, bodyOfObject_, contactSurface(samples), tolerance))
    out.push_back({o.objectA, o.objectB, o.depth});
  return out;
}

void RigidBodySystem::advanceHinged(RigidBody& b, const HingeDescription& h, const Vector3r& J, const Vector3r& L,
                                    Real dt) {
  // Rotation about a fixed axis a through p: the joint's reaction acts at p and has no torque
  // about a, so a . (angular momentum about p) changes by a . (L + (x - p) x J), and that
  // momentum is I_a omega with I_a = a^T I a + m |r_perp|^2 (parallel axis).
  const Vector3r& a = h.axis;
  const Vector3r r = b.x - h.point;
  const Vector3r rPerp = r - r.dot(a) * a;
  const Matrix3r R = b.rotation();
  const Real Ia = a.dot(R * b.inertiaBody * R.transpose() * a) + b.mass * rPerp.squaredNorm();
  Real omega = b.w.dot(a) + a.dot(L + r.cross(J)) / Ia;
  if (h.motor) {
    // Velocity motor: the impulse that reaches the target speed, within maxTorque dt.
    const Real maxImpulse = h.maxTorque * dt;
    omega += std::clamp(Ia * (h.targetVelocity - omega), -maxImpulse, maxImpulse) / Ia;
  }
  b.rotateAbout(h.point, a, omega * dt);
  b.w = omega * a;
  b.v = b.w.cross(b.x - h.point);
}

const std::vector<PoseUpdate>& RigidBodySystem::poses(bool onlyChanged) {
  written_.resize(bodies_.size());
  poses_.clear();
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const RigidBody& b = bodies_[i];
    const WrittenState now{b.x, b.v, b.w, b.q};
    // Exact comparison: any change at all is given (a body at rest repeats its state bit for bit).
    const bool samePose = onlyChanged && written_[i].x == now.x && written_[i].q.coeffs() == now.q.coeffs();
    if (samePose && written_[i].v == now.v && written_[i].w == now.w) continue;
    written_[i] = now;
    poses_.push_back({b.object, b.pose(), !samePose});
  }
  return poses_;
}

MovingBodyState RigidBodySystem::state(std::size_t body) const {
  const RigidBody& b = bodies_[body];
  MovingBodyState s;
  s.name = b.name;
  s.motion = b.motion;
  s.object = b.object;
  s.mass = b.mass;
  s.reach = b.reach;
  s.x = b.x;
  s.x0 = b.x0;
  s.q = b.q;
  s.v = b.v;
  s.w = b.w;
  s.fluidForce = b.fluidForce;
  s.fluidTorque = b.fluidTorque;
  return s;
}

void RigidBodySystem::restoreState(std::size_t body, const MovingBodyState& s) {
  RigidBody& b = bodies_[body];
  b.x = s.x;
  b.q = s.q;
  b.v = s.v;
  b.w = s.w;
  b.fluidForce = s.fluidForce;
  b.fluidTorque = s.fluidTorque;
}

Vector3r RigidBodySystem::momentum() const {
  Vector3r p = Vector3r::Zero();
  for (const RigidBody& b : bodies_)
    if (b.motion == BodyMotion::Dynamic) p += b.mass * b.v;
  return p;
}

std::string RigidBodySystem::csvHeader() const {
  return "time,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz,fx,fy,fz,tx,ty,tz\n";
}

std::string RigidBodySystem::csvRows(double time) const {
  std::ostringstream s;
  s.precision(9);
  for (const RigidBody& b : bodies_) {
    s << time << "," << b.name;
    for (const Vector3r* v : {&b.x}) s << "," << (*v)[0] << "," << (*v)[1] << "," << (*v)[2];
    s << "," << b.q.w() << "," << b.q.x() << "," << b.q.y() << "," << b.q.z();
    for (const Vector3r* v : {&b.v, &b.w, &b.fluidForce, &b.fluidTorque}) s << "," << (*v)[0] << "," << (*v)[1] << "," << (*v)[2];
    s << "\n";
  }
  return s.str();
}

void RigidBodySystem::worldMeshes(TriangleMesh& all, std::vector<Index>& body, std::vector<Vector3r>& velocity) const {
  all = TriangleMesh();
  body.clear();
  velocity.clear();
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    const RigidBody& b = bodies_[i];
    const Matrix3r R = b.rotation();
    const Index base = Index(all.vertices.size());
    for (auto& v : b.localMesh.vertices) {
      all.vertices.push_back(b.x + R * v);
      body.push_back(b.object);
      velocity.push_back(b.velocityAt(all.vertices.back()));
    }
    for (auto& t : b.localMesh.triangles) all.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
  }
}

std::string RigidBodySystem::meshesToVtu() const {
  TriangleMesh all;
  std::vector<Index> body;
  std::vector<Vector3r> velocity;
  worldMeshes(all, body, velocity);
  VtuPointCloud cloud(all.vertices.data(), all.vertices.size());
  cloud.setTriangles(all.triangles.data(), all.triangles.size());
  cloud.add("body", body.data());
  cloud.add("velocity", reinterpret_cast<const Real*>(velocity.data()), 3);
  return cloud.serialize();
}

std::unique_ptr<MovingBodies> makeMovingBodies(const std::vector<BoundaryObject>& objects, const BoundaryModel& model,
                                               Real particleRadius, Real fluidDensity, const LogSink& log) {
  if (std::all_of(objects.begin(), objects.end(), [](const BoundaryObject& o) { return o.motion == BodyMotion::Static; }))
    return nullptr;
  std::vector<Real> layerDepth(objects.size());
  for (std::size_t b = 0; b < layerDepth.size(); ++b) layerDepth[b] = model.layerDepth(b);
  // Volume maps have no sample layer to touch with: rigid contact samples the surfaces itself,
  // r apart (the particle walls' default sampling distance).
  const Real contactSpacing = model.implicit() ? particleRadius : Real(0);
  auto bodies = std::make_unique<RigidBodySystem>(objects, model.samples(), std::move(layerDepth), particleRadius, log, contactSpacing);
  bodies->setFluidDensity(fluidDensity);
  return bodies;
}

}  // namespace consph
