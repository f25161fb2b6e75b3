// Whether a triangle mesh is closed (watertight, two-manifold, consistently oriented): the
// divergence-theorem mass properties of a dynamic body (Utilities/MassProperties.h) and the
// winding number hold only then. An open mesh can still report a positive volume (a box without
// its lid does), so the sign of the volume alone does not tell.
#pragma once
#include <cstddef>
#include <string>

#include "Utilities/TriangleMesh.h"

namespace consph {

struct MeshClosure {
  std::size_t openEdges = 0;       // edges of one triangle only (holes, a missing face)
  std::size_t nonManifoldEdges = 0;  // edges shared by more than two triangles
  std::size_t flippedEdges = 0;    // edges whose two triangles run the same way (inconsistent orientation)
  bool closed() const { return openEdges == 0 && nonManifoldEdges == 0 && flippedEdges == 0; }
  // "3 open edges, 1 edge shared by more than two triangles", for messages.
  std::string describe() const;
};

// Vertices at the same position count as one (files often repeat them per face).
MeshClosure checkClosure(const TriangleMesh& mesh);

}  // namespace consph
