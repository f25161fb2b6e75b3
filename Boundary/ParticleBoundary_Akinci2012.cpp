#include "Boundary/ParticleBoundary_Akinci2012.h"

#include <algorithm>
#include <cstdio>
#include <limits>

#include "Boundary/MeshSampling.h"
#include "Boundary/ObjectSampling.h"
#include "Boundary/RestLayer.h"
#include "Simulation/ParamBinding.h"
#include "Simulation/PluginRegistry.h"
#include "Utilities/MassProperties.h"
#include "Utilities/ParallelFor.h"

namespace consph {

namespace {

const PluginRegistration<BoundaryModel> registration{
    "Akinci2012",
    "Particle boundaries: surfaces sampled with particles of volume 1 / sum W (Akinci et al. 2012)",
    ParticleBoundary_Akinci2012::parameters(),
    [](const Params& p, const PluginContext& c) -> std::unique_ptr<BoundaryModel> {
      const Real spacing = c.particleSpacing > 0 ? c.particleSpacing : Real(1.8566) * c.particleRadius;
      auto model = std::make_unique<ParticleBoundary_Akinci2012>(p, c.particleRadius, spacing);
      model->setLog(c.log);
      return model;
    }};
}  // namespace

const BoundParams<ParticleBoundary_Akinci2012::Settings>& ParticleBoundary_Akinci2012::bound() {
  static const BoundParams<Settings> table{
      bind({"samplingDistance", ParamType::Real, 1.0, "distance between boundary particles on the surface, in particle radii r",
            0.25, 4.0},
           &Settings::samplingDistance),
      bind({"surfaceOffset", ParamType::Real, -1.0,
            "distance the sample layer is moved into the solid, in r; -1: computed so the resting fluid's "
            "surface lies on the mesh; 0: samples on the mesh (Akinci 2012)",
            -1.0, 4.0},
           &Settings::surfaceOffset),
      bind({"offsetObjects",
            ParamType::String,
            "auto",
            "which objects get the surface offset: auto (moving bodies, and static objects the initial fluid reaches: "
            "a block drawn up to a wall), moving (dynamic and animated bodies, whose buoyancy depends on it), all, or none",
            -std::numeric_limits<double>::infinity(),
            std::numeric_limits<double>::infinity(),
            {"auto", "moving", "all", "none"}},
           &Settings::offsetObjects),
  };
  return table;
}

std::vector<ParamSpec> ParticleBoundary_Akinci2012::parameters() { return bound().specs(); }

ParticleBoundary_Akinci2012::ParticleBoundary_Akinci2012(const Params& params, Real particleRadius, Real fluidSpacing)
    : ParticleBoundary_Akinci2012(bound().read(params), particleRadius, fluidSpacing) {}

ParticleBoundary_Akinci2012::ParticleBoundary_Akinci2012(const Settings& settings, Real particleRadius, Real fluidSpacing)
    : particleRadius_(particleRadius),
      samplingDistance_(settings.samplingDistance * particleRadius),
      fluidSpacing_(fluidSpacing),
      requestedOffset_(settings.surfaceOffset < 0 ? Real(-1) : settings.surfaceOffset * particleRadius),
      offsetObjects_(settings.offsetObjects) {}

Real ParticleBoundary_Akinci2012::restDistance(const CubicSplineKernel& kernel, Real samplingDistance, Real fluidSpacing) {
  const Real h = kernel.supportRadius(), s = samplingDistance, d = fluidSpacing;
  // A flat layer z = 0 sampled on a square grid, the sample at the origin's mass (rho0 = 1).
  const int nw = int(std::ceil(h / s)) + 2;
  Real wallSum = 0;
  for (int i = -nw; i <= nw; ++i)
    for (int j = -nw; j <= nw; ++j) wallSum += kernel.W(Vector3r(i * s, j * s, 0));
  const Real sampleMass = Real(1) / wallSum;
  // The wall's share at height z, averaged over where the particle sits above the sample grid.
  auto wallDensity = [&](Real z) {
    Real sum = 0;
    int count = 0;
    for (Real a : {Real(0), Real(0.25), Real(0.5)})
      for (Real b : {Real(0), Real(0.25), Real(0.5)}) {
        const Vector3r x(a * s, b * s, z);
        for (int i = -nw; i <= nw; ++i)
          for (int j = -nw; j <= nw; ++j) sum += sampleMass * kernel.W(x - Vector3r(i * s, j * s, 0));
        ++count;
      }
    return sum / count;
  };
  return consph::restDistance(halfLatticeDensity(kernel, d), h, wallDensity);
}

BoundaryEstimate ParticleBoundary_Akinci2012::estimate(const std::vector<BoundaryObject>& objects, const CubicSplineKernel&) const {
  // The lattices sampleBoxSurface and sampleMeshSurface lay before thinning: (n+1)(n+2)/2 points
  // on a triangle whose longest edge is n spacings (a sliver costs as much as a full triangle).
  const double s = double(samplingDistance_);
  BoundaryEstimate e;
  for (const BoundaryObject& o : objects) {
    if (o.isBox) {
      double n[3];
      for (int a = 0; a < 3; ++a) n[a] = std::max(1.0, std::ceil(double(o.boxMax[a] - o.boxMin[a]) / s)) + 1;
      e.samples += 2 * (n[0] * n[1] + n[1] * n[2] + n[0] * n[2]);
      continue;
    }
    for (const auto& t : o.mesh.triangles) {
      const Vector3r &a = o.mesh.vertices[t[0]], &b = o.mesh.vertices[t[1]], &c = o.mesh.vertices[t[2]];
      const double n = std::max(1.0, std::ceil(double(std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()})) / s));
      e.samples += (n + 1) * (n + 2) / 2;
    }
  }
  e.bytes = e.samples * kBytesPerBoundarySample;
  return e;
}

std::vector<Vector3r> ParticleBoundary_Akinci2012::sampleObject(const BoundaryObject& o, Real offset) const {
  return sampleObjectSurface(o, samplingDistance_, offset, log_);
}

bool ParticleBoundary_Akinci2012::fluidReaches(const std::vector<Vector3r>& surfacePoints, const FluidModel& fluid,
                                               Real supportRadius) const {
  // A block drawn up to the surface has its outer lattice layer d/2 from it, its nearest sample
  // at most sqrt(d^2 / 4 + s^2 / 2) away (0.63 d at the default sampling s = r); a block kept
  // d/2 or more off the surface has every particle at least d from every sample.
  const Real reach = Real(0.95) * fluidSpacing_;
  if (surfacePoints.empty() || fluid.size() == 0) return false;
  PointGrid grid;
  grid.build(surfacePoints.data(), surfacePoints.size(), std::max(supportRadius, reach));
  return parallelAny(fluid.size(), [&](std::size_t i) {
    bool near = false;
    grid.forEachNeighbor(fluid.positions[i], reach, [&](Index, const Vector3r&) { near = true; });
    return near;
  });
}

void ParticleBoundary_Akinci2012::initialize(const std::vector<BoundaryObject>& objects, const FluidModel& fluid,
                                             const CubicSplineKernel& kernel) {
  samples_ = BoundarySamples();
  layerDepths_.clear();
  const Real density0 = fluid.density0();
  const Real surfaceOffset = requestedOffset_ >= 0
                       ? requestedOffset_
                       : std::max(Real(0), restDistance(kernel, samplingDistance_, fluidSpacing_) - Real(0.5) * fluidSpacing_);
  std::string offsetNames;  // for the log: which objects moved their layer, and why
  for (std::size_t b = 0; b < objects.size(); ++b) {
    const BoundaryObject& o = objects[b];
    if ((o.mapCellSize != 0 || o.mapThickness != 0) && log_)
      log_(LogLevel::Warning, o.path + ": mapCellSize and mapThickness are volume-map settings; Akinci2012 samples the mesh itself and ignores them");
    // "auto": a static object is sampled on its mesh first, to see whether the fluid starts there.
    std::vector<Vector3r> points;
    bool touched = false;
    if (offsetObjects_ == "auto" && o.motion == BodyMotion::Static && surfaceOffset > 0) {
      points = sampleObject(o, 0);
      touched = fluidReaches(points, fluid, kernel.supportRadius());
    }
    const Real offset = offsets(o, touched) ? surfaceOffset : Real(0);
    if (points.empty() || offset > 0) points = sampleObject(o, offset);
    if (offset > 0) {
      offsetNames += (offsetNames.empty() ? "" : ", ") + (o.name.empty() ? o.path : o.name) + (touched ? " (the fluid starts at it)" : "");
    }
    layerDepths_.push_back(offset);
    // Z-order within the object: neighbours in space become neighbours in memory.
    const auto order = zOrderPermutation(points.data(), points.size(), kernel.supportRadius());
    const std::size_t base = samples_.size();
    samples_.resize(base + points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
      samples_.positions[base + i] = points[order[i]];
      samples_.bodies[base + i] = Index(b);
    }
    // V_k = 1 / sum_l W_kl over this object's particles (self included).
    PointGrid grid;
    grid.build(samples_.positions.data() + base, points.size(), kernel.supportRadius());
    parallelFor(points.size(), [&](std::size_t i) {
      const Vector3r xi = samples_.positions[base + i];
      Real sum = 0;
      grid.forEachNeighbor(xi, kernel.supportRadius(), [&](Index, const Vector3r& xl) { sum += kernel.W(xi - xl); });
      samples_.masses[base + i] = density0 / sum;  // m~_k = rho0 V_k
    });
  }
  if (!offsetNames.empty() && log_) {
    char line[160];
    std::snprintf(line, sizeof(line), "Akinci2012: sample layers %.3g r inside the solids (the resting fluid's surface on the meshes) of: ",
                  double(surfaceOffset / particleRadius_));
    log_(LogLevel::Info, line + offsetNames);
  }
  moved_ = true;
}

bool ParticleBoundary_Akinci2012::offsets(const BoundaryObject& o, bool touched) const {
  if (offsetObjects_ == "all") return true;
  if (offsetObjects_ == "none") return false;
  return o.motion != BodyMotion::Static || touched;  // "moving", "auto"
}

void ParticleBoundary_Akinci2012::findNeighbors(const FluidModel& fluid, const CubicSplineKernel& kernel, NeighborLists& out,
                                                const Real* fluidDensities) {
  if (moved_) {
    grid_.build(samples_.positions.data(), samples_.size(), kernel.supportRadius());
    moved_ = false;
  }
  // With the fluid's sums, the lists carry the densities (the samples' m~_k W_ik evaluated 8
  // pairs at a time while x_k is in cache; a pass of its own over the lists was 4-5 % of a
  // particle-wall dam break's step).
  buildNeighborLists(grid_, fluid.positions.data(), fluid.size(), kernel, false, PairGradients::Vectors, out,
                     fluidDensities ? samples_.masses.data() : nullptr, fluidDensities);
}

}  // namespace consph
