#include "Boundary/VolumeMapBoundary_Bender2019.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "Simulation/ParamBinding.h"
#include "Simulation/PluginRegistry.h"
#include "Utilities/AxisAlignedBox.h"
#include "Utilities/MassProperties.h"
#include "Utilities/ParallelFor.h"
#include "Utilities/Timer.h"
#include "Utilities/TriangleMesh.h"

namespace consph {

namespace {
const PluginRegistration<BoundaryModel> registration{
    "VolumeMap",
    "Implicit boundaries: signed distance and boundary volume on a grid, one virtual boundary particle per fluid "
    "particle and object (Bender et al. 2019); rigid contact through contact points of its own",
    VolumeMapBoundary_Bender2019::parameters(),
    [](const Params& p, const PluginContext& c) -> std::unique_ptr<BoundaryModel> {
      const Real spacing = c.particleSpacing > 0 ? c.particleSpacing : Real(1.8566) * c.particleRadius;
      return std::make_unique<VolumeMapBoundary_Bender2019>(p, c.particleRadius, spacing, c.log, c.sceneDirectory);
    }};
}  // namespace

namespace {
// The axis-aligned box [lo, hi] a container is, if it is one: a "box" object, or a mesh whose
// every vertex is a corner of its bounding box and which encloses that box's volume (an inverted
// unit box OBJ, scaled and moved, as SPlisHSPlasH scenes give their tanks).
bool containerBoxOf(const BoundaryObject& o, Vector3r& lo, Vector3r& hi) {
  if (!o.inverted) return false;
  if (o.isBox) {
    lo = o.boxMin;
    hi = o.boxMax;
    return true;
  }
  if (o.mesh.triangles.size() < 12) return false;
  o.mesh.boundingBox(lo, hi);
  const Vector3r size = hi - lo;
  if (!(size.minCoeff() > 0)) return false;
  const Real tolerance = Real(1e-5) * size.norm();
  for (const Vector3r& v : o.mesh.vertices)
    for (int a = 0; a < 3; ++a)
      if (std::abs(v[a] - lo[a]) > tolerance && std::abs(v[a] - hi[a]) > tolerance) return false;
  const Real boxVolume = size.prod();
  return std::abs(std::abs(computeMassProperties(o.mesh).volume) - boxVolume) < Real(1e-5) * boxVolume;
}

// The solid around container o, the box [lo, hi], as six convex slabs `thickness` thick that do not overlap:
// floor and lid span the whole outline, the x walls stand between them, the z walls between
// those. Each is a (not inverted) box object of its own; the union is the container's shell.
std::vector<BoundaryObject> containerWalls(const BoundaryObject& o, const Vector3r& lo, const Vector3r& hi, Real thickness) {
  const Vector3r t = Vector3r::Constant(thickness);
  const Vector3r outerLo = lo - t, outerHi = hi + t;
  const struct {
    const char* name;
    Vector3r min, max;
  } slabs[6] = {
      {"floor (-y)", outerLo, Vector3r(outerHi[0], lo[1], outerHi[2])},
      {"lid (+y)", Vector3r(outerLo[0], hi[1], outerLo[2]), outerHi},
      {"wall -x", Vector3r(outerLo[0], lo[1], outerLo[2]), Vector3r(lo[0], hi[1], outerHi[2])},
      {"wall +x", Vector3r(hi[0], lo[1], outerLo[2]), Vector3r(outerHi[0], hi[1], outerHi[2])},
      {"wall -z", Vector3r(lo[0], lo[1], outerLo[2]), Vector3r(hi[0], hi[1], lo[2])},
      {"wall +z", Vector3r(lo[0], lo[1], hi[2]), Vector3r(hi[0], hi[1], outerHi[2])},
  };
  std::vector<BoundaryObject> walls;
  for (const auto& slab : slabs) {
    BoundaryObject w = o;
    w.name = (o.name.empty() ? o.path : o.name) + ", " + slab.name;
    w.path = o.path + " (" + slab.name + ")";
    w.inverted = false;
    w.isBox = true;
    w.boxMin = slab.min;
    w.boxMax = slab.max;
    w.mesh = makeBoxMesh(slab.min, slab.max, false);
    walls.push_back(std::move(w));
  }
  return walls;
}
}  // namespace

const BoundParams<VolumeMapBoundary_Bender2019::Settings>& VolumeMapBoundary_Bender2019::bound() {
  static const BoundParams<Settings> table{
      bind({"cellSize", ParamType::Real, 1.0,
            "grid spacing of the distance and volume maps, in particle radii r (2 r: a tank filled to its walls starts at "
            "up to 2.1 rho0 in a corner)",
            0.25, 8.0},
           &Settings::cellSize),
      bind({"surfaceOffset", ParamType::Real, -1.0,
            "distance the boundary surface is moved into the solid, in r; -1: computed so the resting fluid's surface "
            "lies on the mesh (1.35 r with the defaults); 0: the mesh itself (Bender et al. 2019)",
            -1.0, 4.0},
           &Settings::surfaceOffset),
      bind({"approachTolerance", ParamType::Real, 3.0,
            "% of rho0: each step is at most as long as keeps the boundary density a particle moves into within this "
            "of its linear prediction (without it a particle driven into a corner was compressed to 1.5 rho0 and thrown "
            "back at 12.8 m/s; 3, the default: no particle of a dam break above 1.3 rho0 at 1.14-1.25x the steps, "
            "bench/RESULTS.md); 0: off",
            0.0, 100.0},
           &Settings::approachTolerance),
      bind({"offsetObjects",
            ParamType::String,
            "auto",
            "which objects get the surface offset: auto (moving bodies, and static objects the initial fluid reaches: a "
            "block drawn up to a wall), all, or none",
            -std::numeric_limits<double>::infinity(),
            std::numeric_limits<double>::infinity(),
            {"auto", "all", "none"}},
           &Settings::offsetObjects),
      bind({"cache", ParamType::String, "cache",
            "folder that keeps built maps for the next run (relative: to the scene file's folder); \"\": no cache"},
           &Settings::cache),
      bind({"containers",
            ParamType::String,
            "walls",
            "a box container (an axis-aligned box with inverted: true): walls (one map per wall, a convex slab each: a "
            "particle where walls meet gets one virtual particle per wall) or whole (one map for the box, as published: a "
            "corner particle gets every wall's volume at the nearest wall's distance, and a resting tank's corners "
            "never come to rest)",
            -std::numeric_limits<double>::infinity(),
            std::numeric_limits<double>::infinity(),
            {"walls", "whole"}},
           &Settings::containers),
  };
  return table;
}

std::vector<ParamSpec> VolumeMapBoundary_Bender2019::parameters() { return bound().specs(); }

VolumeMapBoundary_Bender2019::VolumeMapBoundary_Bender2019(const Params& params, Real particleRadius, Real fluidSpacing,
                                                           const LogSink& log, const std::string& sceneDirectory)
    : VolumeMapBoundary_Bender2019(bound().read(params), particleRadius, fluidSpacing, log, sceneDirectory) {}

VolumeMapBoundary_Bender2019::VolumeMapBoundary_Bender2019(const Settings& settings, Real particleRadius, Real fluidSpacing,
                                                           const LogSink& log, const std::string& sceneDirectory)
    : particleRadius_(particleRadius),
      fluidSpacing_(fluidSpacing),
      cellSize_(settings.cellSize * particleRadius),
      approachTolerance_(settings.approachTolerance / 100),
      requestedOffset_(settings.surfaceOffset < 0 ? Real(-1) : settings.surfaceOffset * particleRadius),
      offsetObjects_(settings.offsetObjects),
      splitContainers_(settings.containers == "walls"),
      log_(log),
      // A relative folder is the scene's.
      cache_(settings.cache.empty() || sceneDirectory.empty() || std::filesystem::path(settings.cache).is_absolute()
                 ? settings.cache
                 : (std::filesystem::path(sceneDirectory) / settings.cache).string(),
             log) {}

bool VolumeMapBoundary_Bender2019::splitsIntoWalls(const BoundaryObject& o) const {
  Vector3r lo, hi;
  return splitContainers_ && containerBoxOf(o, lo, hi);
}

std::vector<BoundaryObject> VolumeMapBoundary_Bender2019::wallsOf(const BoundaryObject& o, const CubicSplineKernel& kernel,
                                                                  Real surfaceOffset) const {
  // The surface offset (into the solid) and the object's mapThickness (into the fluid) move the
  // walls' inner faces, not the slabs' ends: the box grows by their difference and the slabs
  // are built from it with neither (moved as a map's offset, each slab's end would move too and
  // open a slot along every edge where two walls meet).
  Vector3r lo, hi;
  containerBoxOf(o, lo, hi);
  const Vector3r shift = Vector3r::Constant(surfaceOffset - o.mapThickness);
  // Thick enough that no support ball of a fluid particle reaches through a wall to its back.
  std::vector<BoundaryObject> walls = containerWalls(o, lo - shift, hi + shift, kernel.supportRadius() + 3 * cellSizeOf(o));
  for (BoundaryObject& w : walls) w.mapThickness = 0;
  return walls;
}

BoundaryEstimate VolumeMapBoundary_Bender2019::estimate(const std::vector<BoundaryObject>& objects,
                                                      const CubicSplineKernel& kernel) const {
  // VolumeMap's grid: the bounding box grown by its band (2h + 3 cells), the largest surface
  // offset (4r), the thickness and a cell, one node per cell corner; a distance and a volume per
  // node. An upper bound: only the bricks that reach the band are stored.
  BoundaryEstimate e;
  for (const BoundaryObject& object : objects) {
    const std::vector<BoundaryObject> pieces =
        splitsIntoWalls(object) ? wallsOf(object, kernel, 4 * particleRadius_) : std::vector<BoundaryObject>{object};
    for (const BoundaryObject& o : pieces) {
      const double cell = double(cellSizeOf(o)),
                   margin = 2 * double(kernel.supportRadius()) + 4 * cell + 4 * double(particleRadius_) + double(o.mapThickness);
      Vector3r lo, hi;
      o.mesh.boundingBox(lo, hi);
      double nodes = 1;
      for (int a = 0; a < 3; ++a) nodes *= std::ceil((double(hi[a] - lo[a]) + 2 * margin) / cell) + 1;
      e.cells += nodes;
      e.bytes += nodes * 2 * sizeof(Real);
    }
  }
  return e;
}

void VolumeMapBoundary_Bender2019::initialize(const std::vector<BoundaryObject>& objects, const FluidModel& fluid,
                                              const CubicSplineKernel& kernel) {
  density0_ = fluid.density0();
  kernel_ = kernel;
  Timer timer;
  std::size_t nodes = 0;
  const Real offset = requestedOffset_ >= 0
                          ? requestedOffset_
                          : std::max(Real(0), VolumeMap::restDistance(kernel, particleRadius_, fluidSpacing_) -
                                                  Real(0.5) * fluidSpacing_);
  moving_.assign(objects.size(), 0);
  poses_.assign(objects.size(), ObjectPose());
  pieces_.clear();
  staticPieces_.clear();
  movingPieces_.clear();
  firstPiece_.assign(objects.size(), 0);
  std::string offsetNames;
  for (std::size_t b = 0; b < objects.size(); ++b) {
    const BoundaryObject& o = objects[b];
    moving_[b] = o.motion != BodyMotion::Static;
    // A moving body's displaced volume is its buoyancy: its surface always moves ("auto").
    const bool always = offsetObjects_ == "all" || (offsetObjects_ == "auto" && moving_[b]);
    // The object's maps with its surface moved `shift` into the solid: one, or a box
    // container's six walls (`shapes`, whose slabs already carry the shift).
    const bool split = splitsIntoWalls(o);
    std::vector<BoundaryObject> shapes;
    auto build = [&](Real shift) {
      shapes = split ? wallsOf(o, kernel, shift) : std::vector<BoundaryObject>{o};
      std::vector<std::unique_ptr<VolumeMap>> maps;
      for (const BoundaryObject& shape : shapes) maps.push_back(cache_.obtain(shape, kernel, cellSizeOf(o), split ? Real(0) : shift));
      return maps;
    };
    std::vector<std::unique_ptr<VolumeMap>> maps = build(always ? offset : Real(0));
    // "auto": the initial fluid reaches the surface (a particle within 0.95 d: a block drawn up
    // to it, whose outer layer starts d/2 from it, well inside the resting distance).
    bool touched = false;
    if (offsetObjects_ == "auto" && !always && offset > 0) {
      const Real reach = Real(0.95) * fluidSpacing_;
      for (const auto& map : maps) {
        const VolumeMap& m = *map;
        touched = touched || parallelAny(fluid.size(), [&](std::size_t i) { return m.distance(fluid.positions[i]) < reach; });
      }
      if (touched) maps = build(offset);
    }
    if (always || touched) {
      offsetNames += (offsetNames.empty() ? "" : ", ") + (o.name.empty() ? o.path : o.name);
      Real applied = offset;  // a container's walls are built thick enough for it
      if (!split) applied = maps.front()->surfaceOffset();
      if (applied < offset) {
        char thin[64];
        std::snprintf(thin, sizeof(thin), " (thin: %.3g r)", double(applied / particleRadius_));
        offsetNames += thin;
      }
    }
    // Where each map can give a virtual particle, in its own frame: within h (and a cell of
    // interpolation) of its object's surface, which lies in the mesh's box grown by mapThickness.
    firstPiece_[b] = pieces_.size();
    for (std::size_t p = 0; p < maps.size(); ++p) {
      nodes += maps[p]->nodeCount();
      Vector3r lo, hi;
      shapes[p].mesh.boundingBox(lo, hi);
      const Real reach = kernel.supportRadius() + cellSizeOf(o) + o.mapThickness;
      (moving_[b] ? movingPieces_ : staticPieces_).push_back(pieces_.size());
      pieces_.push_back({std::move(maps[p]), b, lo - Vector3r::Constant(reach), hi + Vector3r::Constant(reach)});
    }
  }
  // The largest boundary density each static map can give a point, for approachStepLimit's
  // shortcut: a virtual particle's m~ W(|x - x_b|) = rho0 V W(s) with V at most the map's largest
  // stored V (trilinear values lie within their corners') and s >= 2r; 1 % over, for the
  // round-off of x_b's placement (|x - x_b| is s to within the round-off of x's coordinates).
  // Deep in a wall (V of the whole ball) this is ~2 rho0, about twice what a particle at a wall
  // meets: loose (it leaves out a minority of the particles), but exact.
  for (const std::size_t p : staticPieces_)
    pieces_[p].densityBound = Real(1.01) * density0_ * pieces_[p].map->largestVolume() * kernel.W(2 * particleRadius_);
  if (!offsetNames.empty() && log_) {
    char line[160];
    std::snprintf(line, sizeof(line), "VolumeMap: surfaces %.3g r inside the solids (the resting fluid's surface on the meshes) of: ",
                  double(offset / particleRadius_));
    log_(LogLevel::Info, line + offsetNames);
  }
  if (log_) {
    char line[160];
    std::snprintf(line, sizeof(line), "VolumeMap: %zu objects (%zu maps), %zu grid nodes, built in %.2f s", objects.size(),
                  pieces_.size(), nodes, timer.seconds());
    log_(LogLevel::Info, line);
  }
  samples_ = BoundarySamples();
  moved_ = true;
}

bool VolumeMapBoundary_Bender2019::virtualParticle(std::size_t piece, const Vector3r& x, const CubicSplineKernel& kernel,
                                                   Vector3r& position, Real& mass, Vector3r& gradient) const {
  Real phi, volume;
  Vector3r phiGradient, volumeGradient;
  const Piece& p = pieces_[piece];
  const std::size_t o = p.object;
  const VolumeMap& map = *p.map;
  if (!moving_[o]) {
    if (p.outOfReach(x) || !map.sample(x, phi, phiGradient, volume, volumeGradient)) return false;
  } else {
    // The map is the body's at t = 0: query it there, turn the gradients into the world.
    const ObjectPose& pose = poses_[o];
    const Vector3r xq = pose.toInitial(x);
    if (p.outOfReach(xq) || !map.sample(xq, phi, phiGradient, volume, volumeGradient)) return false;
    phiGradient = pose.rotation * phiGradient;
    volumeGradient = pose.rotation * volumeGradient;
  }
  const bool follows = phi + Real(0.5) * particleRadius_ > 2 * particleRadius_;  // s = Phi + r/2, else 2r
  const Real s = follows ? phi + Real(0.5) * particleRadius_ : 2 * particleRadius_;
  position = x - s * phiGradient.normalized();
  mass = density0_ * volume;
  // The boundary's density at x_i is rho_b(x) = rho0 V(x) W(s(Phi(x))), a function of x_i alone,
  // so the constraint gradient of Eq. (30) takes its gradient,
  //   grad rho_b = rho0 (W(s) grad V + V W'(s) grad s),  grad s = grad Phi where s follows Phi,
  // written as m~_k times the pair's gradient. grad W(x_i - x_b) alone (the W'(s) n term, as
  // in the reference implementation) misses how V changes: the density solve's prediction then
  // misses ~20 % of the boundary's density change near a wall, and in a concave corner no
  // direction reduces the density (a corner particle stayed at 1.9-2.1 rho0 in a resting
  // column). grad s uses the unit normal, not the interpolated grad Phi, which is shorter (down
  // to ~0.7) in the cells where two walls' distances meet: with it, particles along a tank's
  // vertical edges were trapped at up to 2.6 rho0 (the exact derivative of an over-estimated
  // edge density), while the unit normal keeps pushing them out.
  gradient = (kernel.W(s) / volume) * volumeGradient;
  if (follows) gradient += kernel.dWdr(s) * phiGradient.normalized();
  return true;
}

Real VolumeMapBoundary_Bender2019::approachStepLimit(const FluidModel& fluid, const NeighborLists& neighbors,
                                                       const CubicSplineKernel& kernel, Real longestUseful) const {
  // rho_b(x): the static maps' boundary density, the sum of their virtual particles' m~ W.
  // Moving at v, a particle sees it change by grad rho_b . v dt (the density solve's linear
  // prediction) plus 1/2 kappa (|v| dt)^2, kappa = d^2 rho_b / du^2 along u = v / |v| (central
  // differences over delta = r / 2). The step keeps that miss within e rho0,
  //   dt <= sqrt(2 e rho0 / kappa) / |v|,
  // or, for a particle with headroom h = (1 + e) rho0 - rho_i > 0 (a splash, the free surface),
  // within the longer step over which the whole change, linear part included, stays within h:
  // there the miss cannot compress it.
  // Particles within reach of a moving body are left out. Counted with their velocity relative
  // to the body, a 100 rho0 box landing on a tank's floor through water (bench/stability.py's
  // heavy-body row) drove the step to the 1e-4 s minimum and the fluid it squeezed out to 346 m/s
  // (16 m/s without the limit); with the static floor alone counted for the film under the box,
  // to 0.35 ms and 18.3 m/s (11.3 without; tests/physics/test_volume_map_approach.cpp). Such a
  // film is a closing gap, which leaves only as fast as the step lets the solve push it out (that
  // landing's fastest particle depends on the step even without the limit: bench/RESULTS.md).
  const Real tolerance = approachTolerance_;
  if (tolerance <= 0 || staticPieces_.empty()) return std::numeric_limits<Real>::infinity();
  const Real delta = Real(0.5) * particleRadius_;
  // The virtual particles' m~ W(x - x_b), as virtualParticle places them (the same bits), without
  // the constraint gradients: these two samples per particle near a wall were two thirds of the
  // maps' sampling, and grad V, W'(s) went unused (bench/RESULTS.md, "Volume-map sampling").
  // (rho0 V W(s) is the same value but for round-off; that round-off alone moved a resting
  // tank's fastest particle from 0.044 to 0.059 m/s after 3.5 s, past its test's 0.05.)
  auto staticDensity = [&](const Vector3r& x) {
    Real rho = 0;
    for (const std::size_t p : staticPieces_) {
      Real phi, volume;
      Vector3r phiGradient;
      if (pieces_[p].outOfReach(x) || !pieces_[p].map->sampleValues(x, phi, phiGradient, volume)) continue;
      const Real s = std::max(phi + Real(0.5) * particleRadius_, 2 * particleRadius_);
      const Vector3r position = x - s * phiGradient.normalized();
      const Real mass = density0_ * volume;
      rho += mass * kernel.W(x - position);
    }
    return rho;
  };
  const Real rho0 = density0_;
  // A dynamic schedule: the particles near a wall, which sample the maps twice more, gather in
  // one part of the sorted order; a minimum is exact in any grouping.
  return parallelReduceDynamic(
      fluid.size(), std::numeric_limits<Real>::infinity(), [](Real& into, const Real& from) { into = std::min(into, from); },
      [&](std::size_t i, Real& shortest) {
        const Vector3r v = fluid.velocities[i];
        const Real speed = v.norm();
        if (speed < Real(1e-6)) return;
        const Vector3r x = fluid.positions[i], u = v / speed;
        // At x itself this step's lists hold the virtual particles (findNeighbors, in piece
        // order): staticDensity(x)'s terms in its order, without sampling the maps again (the
        // compiler may fuse the sum's multiply-adds differently: within an ulp).
        Real r0 = 0;
        for (Index e = neighbors.begin(i); e < neighbors.end(i); ++e) {
          const Index k = neighbors.indices[e];
          if (moving_[samples_.bodies[k]]) return;
          r0 += samples_.masses[k] * kernel.W(x - samples_.positions[k]);
        }
        // A particle that cannot shorten the step is left before the maps are sampled, or
        // before the second sample: each of rho_b(x +- delta u) is at most the sum of the
        // densityBounds of the maps within reach there, which bounds kappa from above and so this
        // particle's step from below (the headroom's step is longer still). A slow particle near a
        // wall is left out so; the result is the same wherever it binds.
        const Vector3r ahead = x + delta * u, behind = x - delta * u;
        Real aheadBound = 0, behindBound = 0;
        for (const std::size_t p : staticPieces_) {
          if (!pieces_[p].outOfReach(ahead)) aheadBound += pieces_[p].densityBound;
          if (!pieces_[p].outOfReach(behind)) behindBound += pieces_[p].densityBound;
        }
        // The bound's step in the very operations of `longest` below, each rounding monotonically:
        // a bound at or above kappa gives a step at or below longest's, also at a tie.
        const auto cannotBind = [&](Real kappaBound) {
          return !(kappaBound > 0) || std::sqrt(tolerance * rho0 / (Real(0.5) * kappaBound * speed * speed)) >= longestUseful;
        };
        if (cannotBind((aheadBound - 2 * r0 + behindBound) / (delta * delta))) return;
        const Real rp = staticDensity(ahead);
        if (r0 <= 0 && rp <= 0) return;  // no static wall within reach, now or r/2 on
        if (cannotBind((rp - 2 * r0 + behindBound) / (delta * delta))) return;
        const Real rm = staticDensity(behind);
        const Real kappa = (rp - 2 * r0 + rm) / (delta * delta);
        if (!(kappa > 0)) return;
        const Real curve = Real(0.5) * kappa * speed * speed;  // the miss is curve dt^2
        Real longest = std::sqrt(tolerance * rho0 / curve);
        const Real headroom = (1 + tolerance) * rho0 - fluid.densities[i];
        if (headroom > 0) {
          const Real rate = (rp - rm) / (2 * delta) * speed;
          longest = std::max(longest, 2 * headroom / (rate + std::sqrt(rate * rate + 4 * curve * headroom)));
        }
        shortest = std::min(shortest, longest);
      });
}

Vector3r VolumeMapBoundary_Bender2019::impulseInBox(Index k, const Vector3r& x, const Vector3r& impulse, const Vector3r& lo,
                                                   const Vector3r& hi) const {
  // What the load acts on lies within 2h of x (the feet of the shell points within h of x, the
  // virtual particle within h): a box holding that ball takes all of it, one clear of it none.
  const Real reach = 2 * kernel_.supportRadius();
  if ((x - lo).minCoeff() >= reach && (hi - x).minCoeff() >= reach) return impulse;
  if ((lo - x).cwiseMax(x - hi).cwiseMax(Vector3r::Zero()).squaredNorm() > reach * reach) return Vector3r::Zero();
  const bool sampleInside = insideBox(samples_.positions[k], lo, hi);
  const std::size_t o = samples_.bodies[k];
  const ObjectPose& pose = poses_[o];
  const Vector3r xq = moving_[o] ? pose.toInitial(x) : x;  // the map's frame
  Matrix3r whole, part;
  pieces_[samplePieces_[k]].map->normalMoments(xq, kernel_, [&](const Vector3r& foot) {
    return insideBox(moving_[o] ? Vector3r(pose.centre + pose.rotation * (foot - pose.initialCentre)) : foot, lo, hi);
  }, whole, part);
  // J's components along the surface normals it meets, M M^+ J (M^+ the pseudo-inverse: a flat
  // wall's M has rank 1), are shared out as the moments are, M_part M^+ J; what is left of J
  // (across every normal) goes with the virtual particle.
  const Eigen::SelfAdjointEigenSolver<Matrix3r> eigen(whole);
  const Real largest = eigen.eigenvalues().maxCoeff();
  if (!(largest > 0)) return sampleInside ? impulse : Vector3r::Zero();
  const Vector3r impulseInMap = moving_[o] ? Vector3r(pose.rotation.transpose() * impulse) : impulse;
  Vector3r solved = Vector3r::Zero(), spanned = Vector3r::Zero();  // M^+ J, M M^+ J
  for (int e = 0; e < 3; ++e) {
    const Real lambda = eigen.eigenvalues()[e];
    if (!(lambda > Real(1e-6) * largest)) continue;
    const Vector3r u = eigen.eigenvectors().col(e);
    solved += (u.dot(impulseInMap) / lambda) * u;
    spanned += u.dot(impulseInMap) * u;
  }
  Vector3r share = part * solved;
  if (sampleInside) share += impulseInMap - spanned;
  return moving_[o] ? Vector3r(pose.rotation * share) : share;
}

void VolumeMapBoundary_Bender2019::findNeighbors(const FluidModel& fluid, const CubicSplineKernel& kernel, NeighborLists& out,
                                                 const Real*) {
  out.kernelSums.clear();  // the virtual particles' densities are summed by computeDensities
  const std::size_t n = fluid.size(), pieces = pieces_.size();
  const std::size_t chunks = parallelChunkCount();
  // The particles that sample a map cost several times those that every reach test turns away,
  // and they gather where the fluid meets the walls: in a Z-sorted dam break one thread's half
  // held most of them, and the other waited. The ranges hold equal shares of the last call's
  // virtual particles (a particle's own cost counted too): the lists come out the same whatever
  // the ranges, which only move the work. After a Z-sort the last counts belong to other
  // particles, but to ones nearby (the order changes little), which is all a balance needs.
  constexpr std::size_t kCostPerParticle = 1, kCostPerVirtualParticle = 8;
  if (out.offsets.size() == n + 1)
    work_.balance(n, chunks, [&](std::size_t i) { return kCostPerParticle * i + kCostPerVirtualParticle * std::size_t(out.offsets[i]); });
  else
    work_.balance(n, chunks, [](std::size_t i) { return i; });
  out.offsets.resize(n + 1);
  out.offsets[0] = 0;
  // One pass over the maps: each thread keeps the virtual particles of its contiguous chunk of
  // fluid particles in its own buffer (kept across steps, so steady steps allocate nothing), and
  // the buffers are then copied into the CSR arrays in chunk order. A count pass and a fill pass
  // would sample every map twice per particle.
  chunkScratch_.resize(chunks);
  for (auto& found : chunkScratch_) found.clear();  // no earlier call's particles reach the copy below
  std::vector<std::size_t> chunkBegin(chunks, n);
  parallelChunks(work_, [&](std::size_t t, std::size_t begin, std::size_t end) {
    chunkBegin[t] = begin;
    // A local header: no false sharing of the vectors' sizes between threads.
    std::vector<VirtualParticle> found = std::move(chunkScratch_[t]);
    for (std::size_t i = begin; i < end; ++i) {
      const Vector3r xi = fluid.positions[i];
      Index count = 0;
      for (std::size_t p = 0; p < pieces; ++p) {
        VirtualParticle v;
        if (!virtualParticle(p, xi, kernel, v.position, v.mass, v.gradient)) continue;
        const std::size_t o = pieces_[p].object;
        // The body's velocity where the fluid particle is: the boundary density there, a function
        // of x_i in the body's frame, changes at grad rho_b . (v_i - v_body(x_i)).
        v.velocity = moving_[o] ? poses_[o].velocityAt(xi) : Vector3r::Zero();
        v.body = Index(o);
        v.piece = Index(p);
        found.push_back(v);
        ++count;
      }
      out.offsets[i + 1] = count;
    }
    chunkScratch_[t] = std::move(found);
  });
  for (std::size_t i = 0; i < n; ++i) out.offsets[i + 1] += out.offsets[i];
  const std::size_t pairs = out.offsets[n];
  samples_.resize(pairs);
  samplePieces_.resize(pairs);
  out.indices.resize(pairs);
  out.gradW.resize(pairs);
  out.gradFactors.clear();
  parallelFor(chunks, [&](std::size_t t) {
    Index e = out.offsets[chunkBegin[t]];
    for (const VirtualParticle& v : chunkScratch_[t]) {
      samples_.positions[e] = v.position;
      samples_.velocities[e] = v.velocity;
      samples_.masses[e] = v.mass;
      samples_.bodies[e] = v.body;
      samplePieces_[e] = v.piece;
      out.indices[e] = e;
      out.gradW[e] = v.gradient;
      ++e;
    }
  });
}

}  // namespace consph
