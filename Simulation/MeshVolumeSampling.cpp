#include "Simulation/MeshVolumeSampling.h"

#include <cmath>

#include "Utilities/Error.h"
#include "Utilities/MassProperties.h"
#include "Utilities/ParallelFor.h"

namespace consph {

std::vector<Vector3r> sampleMeshVolume(const TriangleMesh& mesh, BlockLattice lattice, Real spacing, Real radius) {
  if (lattice != BlockLattice::CellCentred && lattice != BlockLattice::SplishSplashRegular)
    throw InputError("a mesh volume is sampled on the cellCentred or the splishsplashRegular lattice");
  Vector3r lo, hi;
  mesh.boundingBox(lo, hi);
  const bool cellCentred = lattice == BlockLattice::CellCentred;
  const double step = cellCentred ? double(spacing) : 2 * double(radius);
  long n[3];
  for (int a = 0; a < 3; ++a) {
    const double extent = double(hi[a] - lo[a]) / step;
    // Cell-centred: whole cells only; SPlisHSPlasH: every voxel whose corner lies in the box.
    n[a] = long(cellCentred ? std::floor(extent + 1e-9) : std::floor(extent) + 1);
  }
  std::vector<Vector3r> candidates;
  for (long i = 0; i < n[0]; ++i)
    for (long j = 0; j < n[1]; ++j)
      for (long k = 0; k < n[2]; ++k)
        candidates.push_back(lo + Vector3r(Real(step * (double(i) + 0.5)), Real(step * (double(j) + 0.5)), Real(step * (double(k) + 0.5))));
  std::vector<char> inside(candidates.size(), 0);
  parallelForDynamic(candidates.size(), [&](std::size_t c) { inside[c] = windingNumber(mesh, candidates[c]) > Real(0.5); });
  std::vector<Vector3r> points;
  for (std::size_t c = 0; c < candidates.size(); ++c)
    if (inside[c]) points.push_back(candidates[c]);
  return points;
}

}  // namespace consph
