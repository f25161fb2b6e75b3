#include "Boundary/ObjectSampling.h"

#include <algorithm>
#include <cmath>

#include "Boundary/MeshSampling.h"
#include "Utilities/MassProperties.h"

namespace consph {

namespace {

// The box sampled for an axis-aligned box object: shrunk by `offset` (a body) or grown (a
// container). A body thinner than offset + one sampling distance keeps one sample spacing of
// thickness around its mid-plane instead of turning inside out.
Vector3r offsetBox(const BoundaryObject& o, Real offset, Real spacing, bool lower) {
  Vector3r lo = o.boxMin, hi = o.boxMax;
  for (int a = 0; a < 3; ++a) {
    Real shift = o.inverted ? -offset : offset;
    if (!o.inverted) shift = std::min(shift, std::max(Real(0), Real(0.5) * (hi[a] - lo[a] - spacing)));
    lo[a] += shift;
    hi[a] -= shift;
  }
  return lower ? lo : hi;
}

// Signed offset along the triangles' winding normals that moves samples into the solid. The
// winding normals point out of a body and, for a container (whose triangles were flipped when
// loaded), into it; a mesh whose signed volume says it is inside out is handled the other way.
// An open mesh (no enclosed volume) is sampled on its surface.
Real meshNormalOffset(const BoundaryObject& o, Real offset) {
  const Real volume = computeMassProperties(o.mesh).volume;
  Vector3r lo, hi;
  o.mesh.boundingBox(lo, hi);
  if (std::abs(volume) < Real(1e-6) * (hi - lo).prod()) return 0;
  const bool outward = (volume > 0) != o.inverted;  // winding normals point away from the solid
  return outward ? -offset : offset;
}

}  // namespace

std::vector<Vector3r> sampleObjectSurface(const BoundaryObject& o, Real spacing, Real offset, const LogSink& log) {
  return o.isBox ? sampleBoxSurface(offsetBox(o, offset, spacing, true), offsetBox(o, offset, spacing, false), spacing)
                 : sampleMeshSurface(o.mesh, spacing, meshNormalOffset(o, offset), log, o.name.empty() ? o.path : o.name);
}

}  // namespace consph
