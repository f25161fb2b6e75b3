// A triangle mesh in world space (boundary geometry, rigid bodies).
#pragma once
#include <array>
#include <string>
#include <vector>

#include "Utilities/Types.h"

namespace consph {

struct TriangleMesh {
  std::vector<Vector3r> vertices;
  std::vector<std::array<Index, 3>> triangles;

  Real area() const;
  void boundingBox(Vector3r& lo, Vector3r& hi) const;
};

// Axis-aligned box [lo, hi]; triangles face outwards, or inwards when `inverted` (a container).
TriangleMesh makeBoxMesh(const Vector3r& lo, const Vector3r& hi, bool inverted);

// Sphere of `slices` x `stacks` quads (2 slices (stacks - 1) triangles), outward-facing.
TriangleMesh makeSphereMesh(const Vector3r& centre, Real radius, int slices, int stacks);

// Loads OBJ, PLY, STL, ... with assimp (all meshes of the file merged, vertices joined).
// Throws InputError naming the file when it is missing or unreadable.
TriangleMesh loadMesh(const std::string& path);

// x -> R (scale .* x) + translation, R the rotation about `axis` by `angle` (radians).
void transformMesh(TriangleMesh& mesh, const Vector3r& scale, const Vector3r& axis, Real angle, const Vector3r& translation);

// The point of triangle abc closest to p.
// `onFace` (optional): set when the closest point lies inside the face, not on an edge or a vertex.
Vector3r closestPointOnTriangle(const Vector3r& p, const Vector3r& a, const Vector3r& b, const Vector3r& c,
                                bool* onFace = nullptr);

// Distance t > 1e-9 along the ray o + t dir at which it crosses triangle abc, infinity when it
// misses or runs parallel to it (Moeller & Trumbore 1997; edges and vertices count as hits).
Real rayTriangleDistance(const Vector3r& o, const Vector3r& dir, const Vector3r& a, const Vector3r& b, const Vector3r& c);

// Signed solid angle of triangle abc seen from p (positive when p is behind its winding normal:
// inside a closed mesh with outward normals), in steradians (Van Oosterom & Strackee 1983).
double triangleSolidAngle(const Vector3r& p, const Vector3r& a, const Vector3r& b, const Vector3r& c);

}  // namespace consph
