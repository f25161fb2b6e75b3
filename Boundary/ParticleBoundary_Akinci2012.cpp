#include "Boundary/ParticleBoundary_Akinci2012.h"

#include "Boundary/MeshSampling.h"
#include "Simulation/PluginRegistry.h"

namespace consph {

namespace {
const PluginRegistration<BoundaryModel> registration{
    "Akinci2012",
    "Particle boundaries: surfaces sampled with particles of volume 1 / sum W (Akinci et al. 2012)",
    ParticleBoundary_Akinci2012::parameters(),
    [](const Params& p, const PluginContext& c) -> std::unique_ptr<BoundaryModel> {
      return std::make_unique<ParticleBoundary_Akinci2012>(p, c.particleRadius);
    }};
}  // namespace

std::vector<ParamSpec> ParticleBoundary_Akinci2012::parameters() {
  return {{"samplingDistance", ParamType::Real, 1.0,
           "distance between boundary particles on the surface, in particle radii r", 0.25, 4.0}};
}

ParticleBoundary_Akinci2012::ParticleBoundary_Akinci2012(const Params& params, Real particleRadius)
    : samplingDistance_(params.real("samplingDistance") * particleRadius) {}

void ParticleBoundary_Akinci2012::initialize(const std::vector<BoundaryObject>& objects, Real density0,
                                             const CubicSplineKernel& kernel) {
  samples_ = BoundarySamples();
  for (std::size_t b = 0; b < objects.size(); ++b) {
    const BoundaryObject& o = objects[b];
    std::vector<Vector3r> points = o.isBox ? sampleBoxSurface(o.boxMin, o.boxMax, samplingDistance_)
                                           : sampleMeshSurface(o.mesh, samplingDistance_);
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
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t i = 0; i < std::ptrdiff_t(points.size()); ++i) {
      const Vector3r xi = samples_.positions[base + i];
      Real sum = 0;
      grid.forEachNeighbor(xi, kernel.supportRadius(), [&](Index, const Vector3r& xl) { sum += kernel.W(xi - xl); });
      samples_.masses[base + i] = density0 / sum;  // m~_k = rho0 V_k
    }
  }
  moved_ = true;
}

void ParticleBoundary_Akinci2012::findNeighbors(const FluidModel& fluid, const CubicSplineKernel& kernel, NeighborLists& out) {
  if (moved_) {
    grid_.build(samples_.positions.data(), samples_.size(), kernel.supportRadius());
    moved_ = false;
  }
  buildNeighborLists(grid_, fluid.positions.data(), fluid.size(), kernel, false, out);
}

}  // namespace consph
