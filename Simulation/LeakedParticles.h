// Fluid particles that ended up inside a wall: the run's "particles lost" record. A run stops
// when a particle leaves the domain, but one that slips through a wall and stays inside the
// solid (or in the gap between a container and the domain's edge) would go unnoticed.
#pragma once
#include <cstddef>
#include <vector>

#include "Simulation/BoundaryModel.h"

namespace consph {

// How many of `positions` lie deeper than `depth` inside the solid of a static object: inside
// a body, or outside a container (an inverted object: a box, or a closed mesh; an open
// container mesh has no outside to tell, and moving objects are skipped). Boxes are exact,
// meshes use the winding number and the distance to their triangles (Utilities/TriangleBvh).
std::size_t countParticlesInsideSolids(const std::vector<BoundaryObject>& objects, const std::vector<Vector3r>& positions,
                                       Real depth);

}  // namespace consph
