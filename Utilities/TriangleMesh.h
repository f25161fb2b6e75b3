// A triangle mesh in world space (boundary geometry, rigid bodies).
#pragma once
#include <array>
#include <string>
#include <vector>

#include "Simulation/Common.h"

namespace consph {

struct TriangleMesh {
  std::vector<Vector3r> vertices;
  std::vector<std::array<Index, 3>> triangles;

  Real area() const;
  void boundingBox(Vector3r& lo, Vector3r& hi) const;
};

// Axis-aligned box [lo, hi]; triangles face outwards, or inwards when `inverted` (a container).
TriangleMesh makeBoxMesh(const Vector3r& lo, const Vector3r& hi, bool inverted);

// Loads OBJ, PLY, STL, ... with assimp (all meshes of the file merged, vertices joined).
// Throws InputError naming the file when it is missing or unreadable.
TriangleMesh loadMesh(const std::string& path);

// x -> R (scale .* x) + translation, R the rotation about `axis` by `angle` (radians).
void transformMesh(TriangleMesh& mesh, const Vector3r& scale, const Vector3r& axis, Real angle, const Vector3r& translation);

}  // namespace consph
