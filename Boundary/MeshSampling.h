// Surface sampling of boundary geometry with points about `spacing` apart.
#pragma once
#include <string>
#include <vector>

#include "Simulation/Common.h"
#include "Utilities/Log.h"
#include "Utilities/TriangleMesh.h"

namespace consph {

// A regular lattice on every triangle, then points closer than 0.6 spacing merged, so shared
// edges and tiny triangles do not produce clusters. Each triangle's points are moved by
// `normalOffset` along its unit normal (the winding's: counter-clockwise seen from the tip), at
// most half the way to the next surface behind them (thin parts keep a mid-plane layer); moved
// faces are closed at convex creases and trimmed where they overlap. O(n log n) in the number of
// samples (Utilities/TriangleBvh.h); work that runs past ~2 s logs progress lines to `log`,
// naming the mesh `name`.
std::vector<Vector3r> sampleMeshSurface(const TriangleMesh& mesh, Real spacing, Real normalOffset = 0, const LogSink& log = {},
                                        const std::string& name = "");

// Closes the strips and corner holes that moving triangles apart by `normalOffset` opens
// along convex creases: arcs of radius |normalOffset| about the crease, a point per vertex.
void addCreaseSamples(const TriangleMesh& mesh, Real spacing, Real normalOffset, std::vector<Vector3r>& points);

// Removes every point closer than 0.98 distances[i] to some triangle.
void dropPointsNearerThan(const TriangleMesh& mesh, const std::vector<Real>& distances, std::vector<Vector3r>& points);

// Regular grids on the six faces of the box [lo, hi], edges and corners once.
std::vector<Vector3r> sampleBoxSurface(const Vector3r& lo, const Vector3r& hi, Real spacing);

// Greedy thinning: keeps a point unless an earlier kept point lies within minDistance.
std::vector<Vector3r> thinPoints(const std::vector<Vector3r>& points, Real minDistance);

}  // namespace consph
