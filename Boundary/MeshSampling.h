// Surface sampling of boundary geometry with points about `spacing` apart.
#pragma once
#include <vector>

#include "Simulation/Common.h"
#include "Utilities/TriangleMesh.h"

namespace consph {

// A regular lattice on every triangle, then points closer than 0.6 spacing merged, so shared
// edges and tiny triangles do not produce clusters.
std::vector<Vector3r> sampleMeshSurface(const TriangleMesh& mesh, Real spacing);

// Regular grids on the six faces of the box [lo, hi], edges and corners once.
std::vector<Vector3r> sampleBoxSurface(const Vector3r& lo, const Vector3r& hi, Real spacing);

// Greedy thinning: keeps a point unless an earlier kept point lies within minDistance.
std::vector<Vector3r> thinPoints(const std::vector<Vector3r>& points, Real minDistance);

}  // namespace consph
