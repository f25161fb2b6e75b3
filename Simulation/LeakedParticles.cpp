#include "Simulation/LeakedParticles.h"

#include <cmath>

#include "Utilities/MeshClosure.h"
#include "Utilities/ParallelFor.h"
#include "Utilities/TriangleBvh.h"

namespace consph {

std::size_t countParticlesInsideSolids(const std::vector<BoundaryObject>& objects, const std::vector<Vector3r>& positions,
                                       Real depth) {
  std::vector<char> inside(positions.size(), 0);
  for (const BoundaryObject& o : objects) {
    if (o.motion != BodyMotion::Static) continue;
    if (o.isBox) {
      // Depth into the box (> 0 inside) and distance outside it, per axis.
      parallelFor(positions.size(), [&](std::size_t i) {
        const Vector3r& x = positions[i];
        const Real into = std::min((x - o.boxMin).minCoeff(), (o.boxMax - x).minCoeff());
        if (o.inverted ? -into > depth : into > depth) inside[i] = 1;
      });
      continue;
    }
    if (o.inverted && !checkClosure(o.mesh).closed()) continue;
    const TriangleBvh surface(o.mesh);
    parallelForDynamic(positions.size(), [&](std::size_t i) {
      if (inside[i]) return;
      const Vector3r& x = positions[i];
      const bool inMesh = std::abs(surface.windingNumber(x)) > Real(0.5);  // a container's faces point inwards
      if (inMesh != o.inverted && !surface.anyTriangleCloserThan(x, depth)) inside[i] = 1;
    });
  }
  std::size_t count = 0;
  for (char c : inside) count += std::size_t(c);
  return count;
}

}  // namespace consph
