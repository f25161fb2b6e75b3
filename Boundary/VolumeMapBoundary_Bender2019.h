// Volume-map boundaries after
//   J. Bender, T. Kugelstadt, M. Weiler, D. Koschier: Volume maps: an implicit boundary
//   representation for SPH. MIG 2019 (also: Implicit frictional boundary handling for SPH,
//   IEEE TVCG 2020).
// Every step, each fluid particle i within h of an object's surface gets one virtual boundary
// particle of that object at x_b = x_i - max(Phi + r/2, 2r) n, mass rho0 V(x_i) (VolumeMap),
// which the solvers, the boundary pressure treatments and the forces then use like an Akinci
// sample (BoundarySamples, rebuilt every step). One difference: a virtual particle has one fluid
// neighbour, so MLS extrapolation's fit is its weighted average, p_k = p_i (mirroring's value,
// with extrapolation's diagonal); the simulation warns about that combination. The virtual particle never comes closer
// than 2r, where grad W is strong: nothing slips between samples or through a thin layer, and
// there are no boundary particles to store or to search.
// Where the boundary is: the resting fluid keeps its first layer D = 2.28 r from the surface (the
// virtual particle's density against the lattice's, VolumeMap::restDistance), while a lattice
// particle fills the cube of side d around its centre; so, as for Akinci samples, the surface
// of an object the initial fluid reaches moves D - d/2 into the solid ("auto"), and a block drawn
// up to a container's walls starts at rest (without it, such a block blew up at step 13).
// Moving (dynamic, animated, hinged) bodies keep the map they had at t = 0: a fluid particle is
// taken into the body's frame of then, and the virtual particle's normal and volume gradient
// back into the world; the virtual particle moves with the body's velocity at the fluid
// particle, and the pressure impulses on it go to the body like those on an Akinci sample
// (Eq. 35; RigidBodySystem takes their torque at the fluid particle). Their
// surfaces always move D - d/2 into the solid, as Akinci layers do, so that a body displaces
// its mesh's volume. There are no sample layers for rigid contact to work on, so RigidBodySystem
// samples contact points on every surface of its own (docs/boundary-models.md).
// A box container (an axis-aligned box with "inverted": true) gets one map per wall ("containers":
// "walls", the default): each wall a convex slab, so a particle where walls meet gets one virtual
// particle per wall, each at its own wall's distance. One map for the whole box ("whole", as
// published) puts every wall's volume at the nearest wall's distance: in a corner that
// over-counts the boundary density (a resting tank's corner particles at 1.03-1.08 rho0, never at
// rest, 0.3-0.7 m/s), docs/boundary-models.md "Corners".
#pragma once
#include <memory>
#include <string>

#include "Boundary/VolumeMap.h"
#include "Boundary/VolumeMapCache.h"
#include "Simulation/BoundaryModel.h"
#include "Simulation/Params.h"
#include "Utilities/ParallelFor.h"

namespace consph {

template <class Settings>
class BoundParams;

class VolumeMapBoundary_Bender2019 final : public BoundaryModel {
 public:
  // `sceneDirectory`: where a relative "cache" folder is.
  VolumeMapBoundary_Bender2019(const Params& params, Real particleRadius, Real fluidSpacing, const LogSink& log,
                               const std::string& sceneDirectory = "");
  void initialize(const std::vector<BoundaryObject>& objects, const FluidModel& fluid, const CubicSplineKernel& kernel) override;
  BoundaryEstimate estimate(const std::vector<BoundaryObject>& objects, const CubicSplineKernel& kernel) const override;
  void findNeighbors(const FluidModel& fluid, const CubicSplineKernel& kernel, NeighborLists& out, const Real* fluidDensities) override;
  bool implicit() const override { return true; }
  // A virtual particle stands for the surface within h of its fluid particle: its load J is
  // taken apart along the normals of that surface, weighted as they make up grad V
  // (VolumeMap::normalMoments), and each part goes where its surface is; J's component across
  // every normal goes with the virtual particle. A frictionless wall takes only its normal
  // push, so along a tank's floor edge the side wall gets the sideways component and the
  // floor the vertical one (with the whole load at the virtual particle, the side wall read
  // 0.85 x hydrostatic in bench/wall_pressure.py).
  Vector3r impulseInBox(Index k, const Vector3r& x, const Vector3r& impulse, const Vector3r& lo, const Vector3r& hi) const override;

  static std::vector<ParamSpec> parameters();
  // approachTolerance > 0: the longest step over which the boundary density at each fluid particle,
  // moving on at its velocity, stays within approachTolerance rho0 of its linear prediction
  // (the density solve's): 1/2 kappa (|v| dt)^2 <= e rho0, kappa = d^2 rho_b / du^2 along the
  // motion u by central differences over r / 2. Towards a wall, and most in a corner, rho_b
  // grows faster than linearly: without it a particle sliding into a floor / wall corner at 4.4
  // m/s (0.53 r per step) was compressed to 1.54 rho0 beyond what the solve saw and thrown back
  // at 12.8 m/s (bench/RESULTS.md). A particle below (1 + e) rho0 (its rho_i from this step's
  // density pass) may take the longer step over which its whole change stays under that. Static
  // maps only, and no particle within reach of a moving body: the gaps a body closes are closing
  // gaps (the .cpp says what counting them did).
  Real approachStepLimit(const FluidModel& fluid, const NeighborLists& neighbors, const CubicSplineKernel& kernel,
                         Real longestUseful) const override;
  // The maps: one per object, or one per wall of a box container ("containers": "walls").
  std::size_t mapCount() const { return pieces_.size(); }
  const VolumeMap& pieceMap(std::size_t piece) const { return *pieces_[piece].map; }
  // A static map's bound of the boundary density its virtual particle gives any point (0 for a
  // moving body's map): approachStepLimit's shortcut rests on it.
  Real pieceDensityBound(std::size_t piece) const { return pieces_[piece].densityBound; }
  std::size_t pieceObject(std::size_t piece) const { return pieces_[piece].object; }
  // The first map of an object (its only one unless it is a box container split into walls).
  const VolumeMap& map(std::size_t object) const { return *pieces_[firstPiece_[object]].map; }
  // Maps loaded from / built for the cache in the last initialize() (VolumeMapCache).
  const VolumeMapCache& cache() const { return cache_; }

 protected:
  // A moving object's map moves with it: its virtual particles are looked up in the map's frame.
  void onPose(std::size_t object, const ObjectPose& pose) override { poses_[object] = pose; }

 private:
  // The virtual particle of map `piece` for a fluid particle at x (position, mass and the pair's
  // gradient); false if x is h or more from its surface.
  bool virtualParticle(std::size_t piece, const Vector3r& x, const CubicSplineKernel& kernel, Vector3r& position, Real& mass,
                       Vector3r& gradient) const;

  // The parameters as declared (lengths in particle radii, the cache folder as written), each
  // declared once with its place here (Simulation/ParamBinding.h); the constructor derives the
  // members below from them.
  struct Settings {
    Real cellSize, surfaceOffset, approachTolerance;
    std::string offsetObjects, cache, containers;
  };
  static const BoundParams<Settings>& bound();
  VolumeMapBoundary_Bender2019(const Settings& settings, Real particleRadius, Real fluidSpacing, const LogSink& log,
                               const std::string& sceneDirectory);

  // A box container whose maps are its six walls ("containers": "walls"): an inverted "box", or an
  // inverted mesh that is an axis-aligned box (SPlisHSPlasH's UnitBox.obj tanks).
  bool splitsIntoWalls(const BoundaryObject& o) const;
  // Those walls, convex slabs, with the container's inner faces moved `surfaceOffset` into the
  // solid (and the object's mapThickness back into the fluid).
  std::vector<BoundaryObject> wallsOf(const BoundaryObject& o, const CubicSplineKernel& kernel, Real surfaceOffset) const;
  // m: the object's mapCellSize, else the model's cellSize.
  Real cellSizeOf(const BoundaryObject& o) const { return o.mapCellSize > 0 ? o.mapCellSize * particleRadius_ : cellSize_; }

  Real particleRadius_;
  Real fluidSpacing_;          // m, the fluid lattice spacing d
  Real cellSize_;              // m
  Real approachTolerance_;     // fraction of rho0; 0: no approach step limit
  Real requestedOffset_;       // m; negative: computed, D - d/2
  std::string offsetObjects_;  // "auto", "all" or "none"
  bool splitContainers_;       // "containers": "walls"
  Real density0_ = 1000;
  CubicSplineKernel kernel_;  // initialize()'s, for impulseInBox
  LogSink log_;
  VolumeMapCache cache_;
  struct Piece {
    std::unique_ptr<VolumeMap> map;
    std::size_t object;
    // The box, in the map's frame, outside which it gives no virtual particle: a cheap test
    // before the grid look-up (a tank's six walls are six maps, and most particles are far
    // from most walls).
    Vector3r reachLo, reachHi;
    // x (in the map's frame) outside that box. Written out: Eigen's minCoeff of the differences
    // was a call of its own per map and particle (2 % of a volume-map dam break's step).
    Real densityBound = 0;  // static maps: the largest rho0 V W(s) a point can get from it, 1 % over
    bool outOfReach(const Vector3r& x) const {
      return x[0] < reachLo[0] || x[1] < reachLo[1] || x[2] < reachLo[2] || x[0] > reachHi[0] || x[1] > reachHi[1] || x[2] > reachHi[2];
    }
  };
  std::vector<Piece> pieces_;
  std::vector<std::size_t> staticPieces_, movingPieces_;  // the pieces of static / moving objects
  std::vector<std::size_t> firstPiece_;  // per object
  std::vector<Index> samplePieces_;      // per virtual particle (pair): its map
  // findNeighbors' per-chunk buffers: a virtual particle as found, before it goes into the lists.
  struct VirtualParticle {
    Vector3r position, velocity, gradient;
    Real mass;
    Index body, piece;
  };
  std::vector<std::vector<VirtualParticle>> chunkScratch_;
  WorkPartition work_;  // findNeighbors' ranges of fluid particles (workChunkCount())
  std::vector<char> moving_;          // per object: dynamic or animated
  std::vector<ObjectPose> poses_;     // per object; identity for static ones
};

}  // namespace consph
