// Particle boundaries after
//   N. Akinci, M. Ihmsen, G. Akinci, B. Solenthaler, M. Teschner: Versatile rigid-fluid coupling
//   for incompressible SPH. ACM Transactions on Graphics 31(4), 2012.
// Boundary surfaces are sampled with particles; particle k gets the volume
// V_k = 1 / sum_l W_kl over the particles l of the same object, and the mass m~_k = rho0 V_k.
//
// Where the sample layer sits: a resting fluid keeps its first particle layer at the distance D
// from a sample layer at which that layer has rest density (about one lattice spacing d), and a
// lattice particle fills the cube of side d around its centre, so samples on the mesh leave a
// gap of D - d/2 of missing fluid around every object: a floating body displaces that much
// more and floats too high (the often reported need for bodies several times denser than water
// to sink). By default the layers of moving bodies are moved D - d/2 into the solid, computed
// for the scene's kernel, sampling and lattice (restDistance), so the fluid's surface lies on
// their meshes. A static object keeps its samples on the mesh (for a container the gap only
// narrows it by about one radius per wall, and the bundled scenes and validation tests place
// their fluid for samples on the mesh) unless the initial fluid reaches it: a block drawn up to
// a wall puts its outer lattice layer d/2 from the surface, deep inside the layer D the fluid
// keeps from samples on the mesh (1.78 rho0 in a corner), and the push-out through a concave
// corner blew every such run up. Then ("auto", the default) that object's layer moves D - d/2
// into the solid as well, and the block starts at rest density.
#pragma once
#include <string>

#include "Simulation/BoundaryModel.h"
#include "Simulation/Params.h"

namespace consph {

template <class Settings>
class BoundParams;

class ParticleBoundary_Akinci2012 final : public BoundaryModel {
 public:
  ParticleBoundary_Akinci2012(const Params& params, Real particleRadius, Real fluidSpacing);
  void initialize(const std::vector<BoundaryObject>& objects, const FluidModel& fluid, const CubicSplineKernel& kernel) override;
  BoundaryEstimate estimate(const std::vector<BoundaryObject>& objects, const CubicSplineKernel& kernel) const override;
  void findNeighbors(const FluidModel& fluid, const CubicSplineKernel& kernel, NeighborLists& out, const Real* fluidDensities) override;
  Real layerDepth(std::size_t object) const override { return object < layerDepths_.size() ? layerDepths_[object] : Real(0); }

  static std::vector<ParamSpec> parameters();

  // D: the distance from a flat sample layer (spacing `samplingDistance`) at which the first
  // layer of a fluid lattice of spacing `fluidSpacing` has rest density (bisection).
  static Real restDistance(const CubicSplineKernel& kernel, Real samplingDistance, Real fluidSpacing);

  void setLog(const LogSink& log) { log_ = log; }

 private:
  // Does o's layer move into the solid? `touched`: the initial fluid reaches o's surface.
  bool offsets(const BoundaryObject& o, bool touched) const;
  // Does a particle of `fluid` start within 0.95 lattice spacings of `surfacePoints`?
  bool fluidReaches(const std::vector<Vector3r>& surfacePoints, const FluidModel& fluid, Real supportRadius) const;
  std::vector<Vector3r> sampleObject(const BoundaryObject& o, Real offset) const;

  // The parameters as declared (lengths in particle radii), each declared once with its place
  // here (Simulation/ParamBinding.h); the constructor turns them into the members below.
  struct Settings {
    Real samplingDistance, surfaceOffset;
    std::string offsetObjects;
  };
  static const BoundParams<Settings>& bound();
  ParticleBoundary_Akinci2012(const Settings& settings, Real particleRadius, Real fluidSpacing);

  Real particleRadius_;
  Real samplingDistance_;  // m
  Real fluidSpacing_;      // m, the fluid lattice spacing d
  Real requestedOffset_;   // m; negative: computed, D - d/2
  std::string offsetObjects_;  // "auto", "moving", "all" or "none"
  std::vector<Real> layerDepths_;  // per object, m
  LogSink log_;
  PointGrid grid_;
};

}  // namespace consph
