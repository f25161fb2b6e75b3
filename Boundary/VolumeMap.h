// The implicit boundary of one object after
//   J. Bender, T. Kugelstadt, M. Weiler, D. Koschier: Volume maps: an implicit boundary
//   representation for SPH. ACM SIGGRAPH Conference on Motion, Interaction and Games (MIG), 2019.
// Two fields on one regular grid around the object, trilinearly interpolated:
//   Phi(x)  the signed distance to the surface, negative in the solid, positive in the fluid (a
//           container's inside is fluid);
//   V(x)    the boundary volume 0.8 * integral over |xi| < h of gamma(Phi(x + xi)) dxi with
//           gamma = 1 in the solid, W(Phi) / W(0) for 0 < Phi < h, 0 beyond (paper/METHODS.md;
//           0.8 (2r)^3 is the particle volume, the fluid's convention too).
// Phi is exact within a band of 2h + 3 cells around the surface (boxes: analytic); V is
// integrated where a particle can meet the boundary, Phi < h + 2 cells. Only the band is stored:
// the grid is split into bricks of 8^3 nodes and a brick is kept when it reaches the band (a
// tank's interior, a body's core and the far corners of its box hold nothing), so memory grows
// with the surface's area, not with the object's volume. `surfaceOffset`
// moves the surface that far into the solid (Phi + offset), at most to one cell short of a thin
// part's mid-plane: the boundary model uses it to put the resting fluid's surface on the mesh.
// The object's `mapThickness` moves it the other way, into the fluid (Phi - thickness, as
// SPlisHSPlasH's maps do), by any amount.
// Meshes must be closed (an open one has no inside: InputError).
#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "Simulation/BoundaryModel.h"
#include "Simulation/Kernel.h"
#include "Utilities/StateArchive.h"

namespace consph {

class VolumeMap {
 public:
  // `cellSize` and `surfaceOffset` in m. Throws InputError for a mesh without triangles.
  VolumeMap(const BoundaryObject& object, const CubicSplineKernel& kernel, Real cellSize, Real surfaceOffset = 0);

  // V at distance Phi = y from a flat boundary (a half-space), m^3: the 1-D integral
  // 0.8 * integral over |z| < h of pi (h^2 - z^2) gamma(y + z) dz.
  static Real halfSpaceVolume(const CubicSplineKernel& kernel, Real y);
  // The distance from a flat boundary at which a resting lattice's first layer (spacing d) has
  // rest density with the virtual particle at max(Phi + r/2, 2r): 2.28 r at d = 1.8566 r.
  static Real restDistance(const CubicSplineKernel& kernel, Real particleRadius, Real spacing);

  // Phi, grad Phi (into the fluid; of length 1 except in cells where two walls' distances meet),
  // V and grad V at x, all of the trilinear interpolants; false where x is h or more from the
  // surface, or off the grid.
  bool sample(const Vector3r& x, Real& phi, Vector3r& phiGradient, Real& volume, Vector3r& volumeGradient) const;
  // sample() without grad V (the boundary's density needs Phi, its gradient and V alone).
  bool sampleValues(const Vector3r& x, Real& phi, Vector3r& phiGradient, Real& volume) const;
  // The largest stored V, which bounds the interpolated V everywhere.
  Real largestVolume() const;
  // Phi alone (large and positive far from the surface or off the grid).
  Real distance(const Vector3r& x) const;
  // The surface a fluid particle at x meets, as normal moments: M = sum |w| n n^T over the points
  // of the shell 0 < Phi < h within h of x, w their weight in grad V's quadrature and n the
  // normal of their foot on the surface, y - Phi(y) n(y) (`whole`), and the same sum over the
  // points whose foot `onPart` accepts (`part`). A force probe's region splits a virtual
  // particle's load so (VolumeMapBoundary_Bender2019::impulseInBox).
  void normalMoments(const Vector3r& x, const CubicSplineKernel& kernel, const std::function<bool(const Vector3r&)>& onPart,
                     Matrix3r& whole, Matrix3r& part) const;

  // The stored nodes (the kept bricks') and their values, brick by brick.
  std::size_t nodeCount() const { return phi_.size(); }
  const std::vector<Real>& distances() const { return phi_; }
  const std::vector<Real>& volumes() const { return volume_; }

  // The whole map as blocks of a state file, and back (Boundary/VolumeMapCache.h stores maps so).
  void save(StateWriter& out) const;
  static std::unique_ptr<VolumeMap> load(const StateReader& in);
  // The offset applied: the requested one, less where the object is too thin for it.
  Real surfaceOffset() const { return offset_; }
  Real thickness() const { return thickness_; }
  Real cellSize() const { return cell_; }

 private:
  VolumeMap() = default;
  static constexpr int kBrick = 4;  // nodes per brick edge
  static constexpr std::size_t kBrickNodes = std::size_t(kBrick) * kBrick * kBrick;
  static constexpr std::size_t kAbsent = std::size_t(-1);
  // Where node (i, j, k) is stored, or kAbsent when its brick was not kept.
  std::size_t storedIndex(int i, int j, int k) const {
    const std::int32_t slot =
        brickSlot_[(std::size_t(k / kBrick) * brickDims_[1] + std::size_t(j / kBrick)) * brickDims_[0] + std::size_t(i / kBrick)];
    if (slot < 0) return kAbsent;
    return std::size_t(slot) * kBrickNodes + (std::size_t(k % kBrick) * kBrick + std::size_t(j % kBrick)) * kBrick + std::size_t(i % kBrick);
  }
  // The grid nodes [begin, end) of brick `brick` (x fastest in the brick index).
  void brickNodes(std::size_t brick, int begin[3], int end[3]) const;
  // Keeps the bricks for which `reachesBand(centre, half diagonal)` holds; phi_ = kFar there.
  void storeBricks(const std::function<bool(const Vector3r& centre, Real halfDiagonal)>& reachesBand);
  // f(i, j, k, stored index) for every grid node of a kept brick, in parallel over bricks.
  template <class NodeFunction>
  void forEachStoredNode(NodeFunction&& f) const;
  Vector3r position(int i, int j, int k) const { return origin_ + cell_ * Vector3r(Real(i), Real(j), Real(k)); }
  // Trilinear weights of x's cell (and the cell's fractions); false off the grid or in a cell
  // with a node outside the exact band.
  bool cellOf(const Vector3r& x, std::size_t corners[8], Real weights[8], Real fractions[3]) const;
  // Phi, grad Phi, V at x and, where volumeGradient is given, grad V (sample, sampleValues).
  bool interpolate(const Vector3r& x, Real& phi, Vector3r& phiGradient, Real& volume, Vector3r* volumeGradient) const;
  // d/dx of corner `corner`'s trilinear weight at the cell fractions, times the cell size.
  static Vector3r weightGradient(int corner, const Real fractions[3]);
  void computeDistances(const BoundaryObject& object);
  void buildBallRule();  // ballOffsets_, ballWeights_ for h_
  void computeVolumes(const CubicSplineKernel& kernel);
  // Phi and its unit gradient at y: analytic for a box, else of the trilinear field; false off
  // the grid (or where the gradient vanishes).
  bool distanceAndNormal(const Vector3r& y, Real& phi, Vector3r& normal) const;
  // Phi where the volume integral needs it: analytic for a box, else interpolated.
  Real exactDistance(const Vector3r& x) const;

  Vector3r origin_ = Vector3r::Zero();
  Real cell_ = 0;
  Real h_ = 0;
  int dims_[3] = {0, 0, 0};
  int brickDims_[3] = {0, 0, 0};
  std::vector<std::int32_t> brickSlot_;  // per brick (x fastest): its slot in phi_ / volume_, or -1
  std::vector<std::uint32_t> bricks_;    // per slot: the brick's index
  Real band_ = 0;  // |Phi| below this is exact; beyond, nodes hold kFar
  std::vector<Real> phi_, volume_;
  std::vector<Vector3r> ballOffsets_;  // quadrature points of the ball |xi| < h and their weights
  std::vector<Real> ballWeights_;
  bool isBox_ = false;
  Vector3r boxMin_ = Vector3r::Zero(), boxMax_ = Vector3r::Zero();
  Real fluidSign_ = 1;
  Real offset_ = 0;     // m, the surface moved into the solid
  Real thickness_ = 0;  // m, the surface moved into the fluid (the object's mapThickness)
  Real surfaceShift() const { return offset_ - thickness_; }  // added to the mesh's distance
};

}  // namespace consph
