// Surface sampling of one boundary object, moved into its solid: the sample layers of particle
// walls and the contact points rigid contact uses with volume maps.
#pragma once
#include <vector>

#include "Simulation/BoundaryModel.h"
#include "Utilities/Log.h"

namespace consph {

// Points about `spacing` apart on the object's surface, moved `offset` into its solid (out of a
// container's inside): a box object on regular face grids of the shrunk (grown) box, a mesh
// along its triangles' normals (an open mesh, which has no inside, on its surface).
std::vector<Vector3r> sampleObjectSurface(const BoundaryObject& o, Real spacing, Real offset, const LogSink& log = {});

}  // namespace consph
