#include "Boundary/VolumeMap.h"

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>

#include "Boundary/MeshSampling.h"
#include "Boundary/RestLayer.h"
#include "Simulation/ResourceEstimate.h"
#include "Utilities/MassProperties.h"
#include "Utilities/ParallelFor.h"
#include "Utilities/TriangleBvh.h"

namespace consph {

namespace {

constexpr Real kFar = std::numeric_limits<Real>::max();

// Signed distance to the axis-aligned box [lo, hi], positive outside.
Real boxDistance(const Vector3r& x, const Vector3r& lo, const Vector3r& hi) {
  const Vector3r c = Real(0.5) * (lo + hi), half = Real(0.5) * (hi - lo);
  const Vector3r q = (x - c).cwiseAbs() - half;
  return q.cwiseMax(Real(0)).norm() + std::min(q.maxCoeff(), Real(0));
}

}  // namespace

VolumeMap::VolumeMap(const BoundaryObject& object, const CubicSplineKernel& kernel, Real cellSize, Real surfaceOffset)
    : cell_(cellSize), offset_(surfaceOffset), thickness_(object.mapThickness) {
  if (!object.isBox && object.mesh.triangles.empty()) throw InputError(object.path + ": the mesh has no triangles");
  const Real h = kernel.supportRadius();
  // Wide enough that the volume quadrature around every node it integrates (-h < Phi < h + 2
  // cells, a ball of radius h) stays inside it, whatever the cell size.
  band_ = 2 * h + 3 * cell_;
  h_ = h;
  Vector3r lo, hi;
  object.mesh.boundingBox(lo, hi);
  // The grid covers every point within the band of the surface.
  const Vector3r margin = Vector3r::Constant(band_ + offset_ + thickness_ + cell_);
  origin_ = lo - margin;
  for (int a = 0; a < 3; ++a) {
    dims_[a] = checkedCount(std::ceil(double(hi[a] - lo[a] + 2 * margin[a]) / double(cell_)) + 1, object.path + ": volume map");
    brickDims_[a] = (dims_[a] + kBrick - 1) / kBrick;
  }
  computeDistances(object);
  // The offset moves the surface into the solid, but a thin part (a plate, a baffle) keeps a
  // solid side: at most to one cell short of its mid-plane (its deepest point).
  Real depth = 0;
  for (Real p : phi_)
    if (p != kFar) depth = std::max(depth, -p);
  offset_ = std::min(offset_, std::max(Real(0), depth - cell_));
  for (Real& p : phi_)
    if (p != kFar) p += surfaceShift();
  buildBallRule();
  computeVolumes(kernel);
}

void VolumeMap::storeBricks(const std::function<bool(const Vector3r& centre, Real halfDiagonal)>& reachesBand) {
  // A brick is kept when one of its nodes may lie in the band: its centre is nearer than the
  // band plus the half diagonal of its nodes' box (distances are 1-Lipschitz). Nodes of a
  // dropped brick would all have held kFar.
  const std::size_t brickCount = std::size_t(brickDims_[0]) * brickDims_[1] * brickDims_[2];
  std::vector<char> keep(brickCount, 0);
  parallelForDynamic(brickCount, [&](std::size_t b) {
    int begin[3], end[3];
    brickNodes(b, begin, end);
    const Vector3r first = position(begin[0], begin[1], begin[2]), last = position(end[0] - 1, end[1] - 1, end[2] - 1);
    keep[b] = reachesBand(Real(0.5) * (first + last), Real(0.5) * (last - first).norm() + Real(1e-6) * cell_);
  }, 64);
  brickSlot_.assign(brickCount, -1);
  bricks_.clear();
  for (std::size_t b = 0; b < brickCount; ++b)
    if (keep[b]) {
      brickSlot_[b] = std::int32_t(bricks_.size());
      bricks_.push_back(std::uint32_t(b));
    }
  phi_.assign(bricks_.size() * kBrickNodes, kFar);
}

void VolumeMap::brickNodes(std::size_t brick, int begin[3], int end[3]) const {
  const std::size_t index[3] = {brick % std::size_t(brickDims_[0]), brick / std::size_t(brickDims_[0]) % std::size_t(brickDims_[1]),
                                brick / (std::size_t(brickDims_[0]) * std::size_t(brickDims_[1]))};
  for (int a = 0; a < 3; ++a) {
    begin[a] = int(index[a]) * kBrick;
    end[a] = std::min(begin[a] + kBrick, dims_[a]);  // the last brick of an axis may be cut short
  }
}

template <class NodeFunction>
void VolumeMap::forEachStoredNode(NodeFunction&& f) const {
  parallelForDynamic(bricks_.size(), [&](std::size_t slot) {
    int begin[3], end[3];
    brickNodes(bricks_[slot], begin, end);
    for (int k = begin[2]; k < end[2]; ++k)
      for (int j = begin[1]; j < end[1]; ++j)
        for (int i = begin[0]; i < end[0]; ++i) f(i, j, k, storedIndex(i, j, k));
  }, 1);
}

void VolumeMap::computeDistances(const BoundaryObject& object) {
  // In the fluid: outside a body's closed surface, inside a container's.
  const Real fluidSign = object.inverted ? Real(-1) : Real(1);
  isBox_ = object.isBox;
  boxMin_ = object.boxMin;
  boxMax_ = object.boxMax;
  fluidSign_ = fluidSign;
  const Real meshBand = band_ + offset_ + thickness_;
  if (object.isBox) {
    // Analytic at every stored node (the bricks within the band).
    storeBricks([&](const Vector3r& c, Real halfDiagonal) {
      return std::abs(boxDistance(c, object.boxMin, object.boxMax)) < meshBand + halfDiagonal;
    });
    forEachStoredNode([&](int i, int j, int k, std::size_t n) {
      phi_[n] = fluidSign * boxDistance(position(i, j, k), object.boxMin, object.boxMax);
    });
    return;
  }
  const TriangleMesh& mesh = object.mesh;
  // The mesh's orientation, from its signed volume: outward normals give a positive one. An open
  // mesh (a plane, a shell) has no inside: its face normals and winding numbers would disagree
  // along every edge, so it is refused.
  const Real signedVolume = computeMassProperties(mesh).volume;
  Vector3r lo, hi;
  mesh.boundingBox(lo, hi);
  if (std::abs(signedVolume) < Real(1e-6) * std::pow((hi - lo).norm(), 3))
    throw InputError(object.path + ": VolumeMap needs a closed mesh (this one encloses no volume); use \"Akinci2012\" for open surfaces");
  const Real outward = signedVolume >= 0 ? Real(1) : Real(-1);
  // Unsigned distance within the band, node by node from the nearest triangle (a BVH query,
  // O(log n) where testing every triangle whose band reaches the node cost thousands of tests
  // per node on a 50 k-face mesh); the sign from that face's normal, or from the winding number
  // where the closest point is on an edge or a vertex (normals disagree there). Exact where the
  // unsigned distance to the mesh is below band + offset + thickness (either may move the
  // surface that far).
  const TriangleBvh surface(mesh);
  storeBricks([&](const Vector3r& c, Real halfDiagonal) { return surface.anyTriangleCloserThan(c, meshBand + halfDiagonal); });
  forEachStoredNode([&](int i, int j, int k, std::size_t n) {
    const Vector3r x = position(i, j, k);
    const TriangleBvh::Nearest nearest = surface.nearestTriangle(x, meshBand);
    if (nearest.triangle == TriangleBvh::kNoTriangle) return;  // outside the band
    bool insideSurface;
    if (nearest.onFace && nearest.distance > 0) {
      const auto& tri = mesh.triangles[nearest.triangle];
      const Vector3r n = (mesh.vertices[tri[1]] - mesh.vertices[tri[0]]).cross(mesh.vertices[tri[2]] - mesh.vertices[tri[0]]);
      insideSurface = outward * n.dot(x - nearest.point) < 0;
    } else {
      insideSurface = std::abs(surface.windingNumber(x)) > Real(0.5);
    }
    phi_[n] = (insideSurface ? -fluidSign : fluidSign) * nearest.distance;
  });
}

void VolumeMap::buildBallRule() {
  // Quadrature over the ball |xi| < h: 6 Gauss-Legendre radii (weight r^2) times 64 directions on
  // a Fibonacci sphere (equal weights 4 pi / 64). gamma is continuous (1 at Phi = 0 from both
  // sides), so a smooth rule converges (unit test: a half-space against a 1-D integral).
  const Real h = h_;
  static const Real gaussX[6] = {-0.9324695142031521, -0.6612093864662645, -0.2386191860831969,
                                 0.2386191860831969,  0.6612093864662645,  0.9324695142031521};
  static const Real gaussW[6] = {0.1713244923791704, 0.3607615730481386, 0.4679139345726910,
                                 0.4679139345726910, 0.3607615730481386, 0.1713244923791704};
  constexpr int kDirections = 64;
  ballOffsets_.clear();
  ballWeights_.clear();
  const Real golden = std::numbers::pi_v<Real> * (Real(3) - std::sqrt(Real(5)));
  for (int g = 0; g < 6; ++g) {
    const Real radius = Real(0.5) * h * (gaussX[g] + 1);
    const Real radialWeight = Real(0.5) * h * gaussW[g] * radius * radius;
    for (int d = 0; d < kDirections; ++d) {
      const Real y = 1 - (Real(d) + Real(0.5)) * Real(2) / kDirections, ring = std::sqrt(1 - y * y);
      const Real theta = golden * Real(d);
      ballOffsets_.push_back(radius * Vector3r(ring * std::cos(theta), y, ring * std::sin(theta)));
      ballWeights_.push_back(radialWeight * 4 * std::numbers::pi_v<Real> / kDirections);
    }
  }
}

void VolumeMap::computeVolumes(const CubicSplineKernel& kernel) {
  const Real h = kernel.supportRadius();
  const std::vector<Vector3r>& offsets = ballOffsets_;
  const std::vector<Real>& weights = ballWeights_;
  const Real w0 = kernel.W0(), wholeBall = Real(0.8) * Real(4) / 3 * std::numbers::pi_v<Real> * h * h * h;
  volume_.assign(phi_.size(), Real(0));
  forEachStoredNode([&](int i, int j, int k, std::size_t n) {
    if (phi_[n] == kFar || phi_[n] >= h + 2 * cell_) return;  // out of reach: V = 0
    if (phi_[n] <= -h) {                                      // the whole ball is solid
      volume_[n] = wholeBall;
      return;
    }
    const Vector3r x = position(i, j, k);
    Real sum = 0;
    for (std::size_t q = 0; q < offsets.size(); ++q) {
      const Real phi = exactDistance(x + offsets[q]);  // beyond the band: far in the fluid
      sum += weights[q] * (phi <= 0 ? Real(1) : (phi < h ? kernel.W(phi) / w0 : Real(0)));
    }
    volume_[n] = Real(0.8) * sum;
  });
}

Real VolumeMap::exactDistance(const Vector3r& x) const {
  return isBox_ ? fluidSign_ * boxDistance(x, boxMin_, boxMax_) + surfaceShift() : distance(x);
}

void VolumeMap::normalMoments(const Vector3r& x, const CubicSplineKernel& kernel,
                              const std::function<bool(const Vector3r&)>& onPart, Matrix3r& whole, Matrix3r& part) const {
  // grad V = 0.8 int gamma'(Phi(x + xi)) grad Phi(x + xi) dxi over |xi| < h comes from the shell
  // 0 < Phi < h (gamma' = W'(Phi) / W(0) there; gamma is 1 in the solid, 0 beyond h), each point
  // pulling along the normal of its foot; the moments weigh each n n^T with |gamma'|, by the rule
  // V was integrated with.
  whole.setZero();
  part.setZero();
  const Real w0 = kernel.W0();
  for (std::size_t q = 0; q < ballOffsets_.size(); ++q) {
    const Vector3r y = x + ballOffsets_[q];
    Real phi;
    Vector3r n;
    if (!distanceAndNormal(y, phi, n) || !(phi > 0 && phi < h_)) continue;
    const Matrix3r moment = (Real(0.8) * ballWeights_[q] * std::abs(kernel.dWdr(phi)) / w0) * (n * n.transpose());
    whole += moment;
    if (onPart(y - phi * n)) part += moment;
  }
}

// Inlined into every sampler: as calls they were a fifth of the volume-map dam break's map
// sampling (perf, bench/RESULTS.md "Volume-map sampling").
[[gnu::always_inline]] inline bool VolumeMap::cellOf(const Vector3r& x, std::size_t corners[8], Real weights[8], Real fractions[3]) const {
  const Vector3r u = (x - origin_) / cell_;
  int c[3];
  for (int a = 0; a < 3; ++a) {
    const Real fl = std::floor(u[a]);
    c[a] = int(fl);
    if (c[a] < 0 || c[a] >= dims_[a] - 1) return false;
    fractions[a] = u[a] - fl;
  }
  // Most cells lie inside one brick: one lookup for all eight corners.
  const bool oneBrick = c[0] % kBrick < kBrick - 1 && c[1] % kBrick < kBrick - 1 && c[2] % kBrick < kBrick - 1;
  const std::size_t base = oneBrick ? storedIndex(c[0], c[1], c[2]) : kAbsent;
  if (oneBrick && base == kAbsent) return false;
  for (int corner = 0; corner < 8; ++corner) {
    const int dx = corner & 1, dy = (corner >> 1) & 1, dz = (corner >> 2) & 1;
    corners[corner] = oneBrick ? base + (std::size_t(dz) * kBrick + std::size_t(dy)) * kBrick + std::size_t(dx)
                               : storedIndex(c[0] + dx, c[1] + dy, c[2] + dz);
    if (corners[corner] == kAbsent || phi_[corners[corner]] == kFar) return false;
    weights[corner] = (dx ? fractions[0] : 1 - fractions[0]) * (dy ? fractions[1] : 1 - fractions[1]) *
                      (dz ? fractions[2] : 1 - fractions[2]);
  }
  return true;
}

[[gnu::always_inline]] inline Vector3r VolumeMap::weightGradient(int corner, const Real fractions[3]) {
  // d/dx of the trilinear weights: +-(the other two axes' weights) / cell.
  const int dx = corner & 1, dy = (corner >> 1) & 1, dz = (corner >> 2) & 1;
  const Real wx = dx ? fractions[0] : 1 - fractions[0], wy = dy ? fractions[1] : 1 - fractions[1],
             wz = dz ? fractions[2] : 1 - fractions[2];
  return Vector3r((dx ? 1 : -1) * wy * wz, (dy ? 1 : -1) * wx * wz, (dz ? 1 : -1) * wx * wy);
}

bool VolumeMap::distanceAndNormal(const Vector3r& y, Real& phi, Vector3r& normal) const {
  if (isBox_) {
    // The box's own distance and its gradient: the nearest face's normal inside, the direction
    // from the nearest box point outside (the two walls of an edge keep their own normals up
    // to the ridge between them, which the trilinear field rounds off).
    const Vector3r c = Real(0.5) * (boxMin_ + boxMax_), half = Real(0.5) * (boxMax_ - boxMin_), rel = y - c;
    const Vector3r q = rel.cwiseAbs() - half;
    Vector3r gradient = Vector3r::Zero();
    if (q.maxCoeff() > 0) {
      const Vector3r outside = q.cwiseMax(Real(0));
      phi = outside.norm();
      for (int a = 0; a < 3; ++a) gradient[a] = rel[a] < 0 ? -outside[a] : outside[a];
      gradient /= phi;
    } else {
      int axis = 0;
      q.maxCoeff(&axis);
      phi = q[axis];
      gradient[axis] = rel[axis] < 0 ? Real(-1) : Real(1);
    }
    phi = fluidSign_ * phi + surfaceShift();
    normal = fluidSign_ * gradient;
    return true;
  }
  std::size_t corners[8];
  Real w[8], f[3];
  if (!cellOf(y, corners, w, f)) return false;
  phi = 0;
  Vector3r gradient = Vector3r::Zero();
  for (int c = 0; c < 8; ++c) {
    const Real p = phi_[corners[c]];
    phi += w[c] * p;
    gradient += p * weightGradient(c, f);
  }
  if (!(gradient.squaredNorm() > Real(1e-24))) return false;
  normal = gradient.normalized();
  return true;
}

// sample() and sampleValues(): grad V only where it is asked for (volumeGradient not null), the
// other sums the same bits either way.
[[gnu::always_inline]] inline bool VolumeMap::interpolate(const Vector3r& x, Real& phi, Vector3r& phiGradient, Real& volume,
                                                         Vector3r* volumeGradient) const {
  std::size_t corners[8];
  Real w[8], f[3];
  if (!cellOf(x, corners, w, f)) return false;
  phi = 0;
  volume = 0;
  phiGradient.setZero();
  if (volumeGradient) volumeGradient->setZero();
  for (int c = 0; c < 8; ++c) {
    const Real p = phi_[corners[c]], v = volume_[corners[c]];
    phi += w[c] * p;
    volume += w[c] * v;
    const Vector3r dw = weightGradient(c, f);
    phiGradient += p * dw;
    if (volumeGradient) *volumeGradient += v * dw;
  }
  phiGradient /= cell_;
  if (volumeGradient) *volumeGradient /= cell_;
  return phi < h_ && volume > 0 && phiGradient.squaredNorm() > Real(1e-12);
}

bool VolumeMap::sample(const Vector3r& x, Real& phi, Vector3r& phiGradient, Real& volume, Vector3r& volumeGradient) const {
  return interpolate(x, phi, phiGradient, volume, &volumeGradient);
}

bool VolumeMap::sampleValues(const Vector3r& x, Real& phi, Vector3r& phiGradient, Real& volume) const {
  return interpolate(x, phi, phiGradient, volume, nullptr);
}

Real VolumeMap::largestVolume() const {
  return parallelMax(volume_.size(), Real(0), [&](std::size_t n) { return volume_[n]; });
}

Real VolumeMap::distance(const Vector3r& x) const {
  std::size_t corners[8];
  Real w[8], f[3];
  if (!cellOf(x, corners, w, f)) return kFar;
  Real phi = 0;
  for (int c = 0; c < 8; ++c) phi += w[c] * phi_[corners[c]];
  return phi;
}

Real VolumeMap::halfSpaceVolume(const CubicSplineKernel& kernel, Real y) {
  const Real h = kernel.supportRadius(), w0 = kernel.W0();
  constexpr int kIntervals = 2000;  // Simpson; gamma has a kink at 0 only, error ~1e-6 relative
  const Real dz = 2 * h / kIntervals;
  Real sum = 0;
  for (int i = 0; i <= kIntervals; ++i) {
    const Real z = -h + dz * Real(i), phi = y + z;
    const Real gamma = phi <= 0 ? Real(1) : (phi < h ? kernel.W(phi) / w0 : Real(0));
    sum += (i == 0 || i == kIntervals ? 1 : (i % 2 ? 4 : 2)) * std::numbers::pi_v<Real> * (h * h - z * z) * gamma;
  }
  return Real(0.8) * sum * dz / 3;
}

Real VolumeMap::restDistance(const CubicSplineKernel& kernel, Real r, Real spacing) {
  return consph::restDistance(halfLatticeDensity(kernel, spacing), kernel.supportRadius(), [&](Real y) {
    return halfSpaceVolume(kernel, y) * kernel.W(std::max(y + Real(0.5) * r, 2 * r));
  });
}

void VolumeMap::save(StateWriter& out) const {
  out.put("origin", std::array<Real, 3>{origin_[0], origin_[1], origin_[2]});
  out.put("cell", cell_);
  out.put("h", h_);
  out.put("dims", std::array<int, 3>{dims_[0], dims_[1], dims_[2]});
  out.put("band", band_);
  out.putVector("brickSlots", brickSlot_);
  out.putVector("phi", phi_);
  out.putVector("volume", volume_);
  out.put("isBox", isBox_);
  out.put("box", std::array<Real, 6>{boxMin_[0], boxMin_[1], boxMin_[2], boxMax_[0], boxMax_[1], boxMax_[2]});
  out.put("fluidSign", fluidSign_);
  out.put("offset", offset_);
  out.put("thickness", thickness_);
}

std::unique_ptr<VolumeMap> VolumeMap::load(const StateReader& in) {
  std::unique_ptr<VolumeMap> m(new VolumeMap());
  const auto origin = in.get<std::array<Real, 3>>("origin");
  m->origin_ = Vector3r(origin[0], origin[1], origin[2]);
  m->cell_ = in.get<Real>("cell");
  m->h_ = in.get<Real>("h");
  const auto dims = in.get<std::array<int, 3>>("dims");
  for (int a = 0; a < 3; ++a) {
    m->dims_[a] = dims[std::size_t(a)];
    m->brickDims_[a] = (m->dims_[a] + kBrick - 1) / kBrick;
  }
  m->band_ = in.get<Real>("band");
  m->brickSlot_ = in.getVector<std::int32_t>("brickSlots");
  if (m->brickSlot_.size() != std::size_t(m->brickDims_[0]) * m->brickDims_[1] * m->brickDims_[2])
    throw InputError(in.file() + ": the volume map's brick table does not match its grid");
  for (std::size_t b = 0; b < m->brickSlot_.size(); ++b)
    if (m->brickSlot_[b] >= 0) {
      if (std::size_t(m->brickSlot_[b]) != m->bricks_.size()) throw InputError(in.file() + ": the volume map's brick table is out of order");
      m->bricks_.push_back(std::uint32_t(b));
    }
  m->phi_ = in.getVector<Real>("phi");
  m->volume_ = in.getVector<Real>("volume");
  m->isBox_ = in.get<bool>("isBox");
  const auto box = in.get<std::array<Real, 6>>("box");
  m->boxMin_ = Vector3r(box[0], box[1], box[2]);
  m->boxMax_ = Vector3r(box[3], box[4], box[5]);
  m->fluidSign_ = in.get<Real>("fluidSign");
  m->offset_ = in.get<Real>("offset");
  m->thickness_ = in.get<Real>("thickness");
  const std::size_t nodes = m->bricks_.size() * kBrickNodes;
  if (m->phi_.size() != nodes || m->volume_.size() != nodes)
    throw InputError(in.file() + ": the volume map's node arrays do not match its grid");
  m->buildBallRule();
  return m;
}

}  // namespace consph
