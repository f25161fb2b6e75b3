#include "Simulation/FluidBlock.h"

#include <cmath>
#include <string>

#include "Utilities/Error.h"

namespace consph {

const std::vector<const char*>& blockLatticeNames() {
  static const std::vector<const char*> names = {"cellCentred", "splishsplashRegular", "splishsplashMoreDense", "splishsplashDense"};
  return names;
}

BlockLattice blockLatticeFromName(const std::string& name) {
  const auto& names = blockLatticeNames();
  for (std::size_t i = 0; i < names.size(); ++i)
    if (name == names[i]) return BlockLattice(i);
  throw InputError("unknown block lattice '" + name + "'");
}

std::array<double, 3> latticeCounts(const FluidBlock& b, Real spacing) {
  std::array<double, 3> n;
  for (int a = 0; a < 3; ++a) n[a] = std::max(1.0, std::floor(double(b.max[a] - b.min[a]) / double(spacing) + 1e-4));
  return n;
}

namespace {

// SPlisHSPlasH's lattice steps (x, y, z) and how far the block shrinks on x and z before they are
// counted (SimulatorBase::createFluidBlocks in its 2.16 sources: the denser modes stagger
// neighbouring rows by up to one step, so they lose one step of room).
struct SplishSplashSteps {
  double x, y, z;       // m
  double shrinkX, shrinkZ;  // m
};

SplishSplashSteps splishsplashSteps(BlockLattice lattice, double r) {
  const double diameter = 2 * r, eps = 1e-9;
  switch (lattice) {
    case BlockLattice::SplishSplashMoreDense: return {diameter, std::sqrt(3.0) * r + eps, diameter, diameter, diameter};
    case BlockLattice::SplishSplashDense: {
      const double x = std::sqrt(6.0) * diameter / 3 + eps;
      return {x, std::sqrt(3.0) * r + eps, diameter, x, diameter};
    }
    default: return {diameter, diameter, diameter, 0, 0};
  }
}

}  // namespace

std::array<double, 3> blockCounts(const FluidBlock& b, Real spacing, Real radius) {
  if (b.lattice == BlockLattice::CellCentred) return latticeCounts(b, spacing);
  const SplishSplashSteps s = splishsplashSteps(b.lattice, double(radius));
  const Vector3r size = b.max - b.min;
  // round(extent / step) - 1 points per axis, the first one 2r in from min: the block's faces
  // stay a particle diameter clear of a wall drawn on them.
  const std::array<double, 3> n = {std::round((double(size[0]) - s.shrinkX) / s.x) - 1, std::round(double(size[1]) / s.y) - 1,
                                   std::round((double(size[2]) - s.shrinkZ) / s.z) - 1};
  if (n[0] <= 1 || n[1] <= 1 || n[2] <= 1) return {0, 0, 0};
  return n;
}

void sampleBlock(const FluidBlock& b, Real spacing, Real radius, std::vector<Vector3r>& positions) {
  const auto counts = blockCounts(b, spacing, radius);
  const long n[3] = {long(counts[0]), long(counts[1]), long(counts[2])};
  if (b.lattice == BlockLattice::CellCentred) {
    const double d = double(spacing);
    for (long i = 0; i < n[0]; ++i)
      for (long j = 0; j < n[1]; ++j)
        for (long k = 0; k < n[2]; ++k)
          positions.push_back(b.min + Vector3r(Real(d * (i + 0.5)), Real(d * (j + 0.5)), Real(d * (k + 0.5))));
    return;
  }
  const double r = double(radius);
  const SplishSplashSteps s = splishsplashSteps(b.lattice, r);
  const Eigen::Vector3d start = b.min.cast<double>() + Eigen::Vector3d::Constant(2 * r);
  for (long i = 0; i < n[0]; ++i)
    for (long j = 0; j < n[1]; ++j)
      for (long k = 0; k < n[2]; ++k) {
        Eigen::Vector3d x = start + Eigen::Vector3d(double(i) * s.x, double(j) * s.y, double(k) * s.z);
        if (b.lattice == BlockLattice::SplishSplashMoreDense) {
          // Alternate layers shift by r along z and along x: a body-centred stacking.
          x += j % 2 == 0 ? Eigen::Vector3d(0, 0, r) : Eigen::Vector3d(r, 0, 0);
        } else if (b.lattice == BlockLattice::SplishSplashDense) {
          // Hexagonal close packing: odd columns shift by r along z (sign alternating with the
          // layer), even layers by half a column step along x.
          x[2] += r;
          if (i % 2 == 1) x[2] += j % 2 == 1 ? -r : r;
          if (j % 2 == 0) x[0] += s.x / 2;
        }
        positions.push_back(x.cast<Real>());
      }
}

}  // namespace consph
