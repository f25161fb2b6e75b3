// Mass, centre of mass and inertia tensor of a closed triangle mesh of uniform density, by the
// divergence theorem: volume integrals of 1, x, x^2, xy become surface integrals over the
// triangles, evaluated exactly per triangle after
//   D. Eberly: Polyhedral Mass Properties (Revisited). Geometric Tools, 2002
//   (the method of B. Mirtich: Fast and Accurate Computation of Polyhedral Mass Properties.
//   Journal of Graphics Tools 1(2), 1996).
#pragma once
#include "Utilities/Types.h"
#include "Utilities/TriangleMesh.h"

namespace consph {

struct MassProperties {
  Real volume = 0;                                // m^3 (negative: the triangles face inwards)
  Vector3r centerOfMass = Vector3r::Zero();       // m
  Matrix3r inertiaPerDensity = Matrix3r::Zero();  // about the centre of mass, m^5 (times density: kg m^2)
};

// The mesh must be closed with outward-facing triangles (counter-clockwise seen from outside).
MassProperties computeMassProperties(const TriangleMesh& mesh);

// Generalised winding number of a closed mesh around p (1 inside, 0 outside), from the solid
// angles of its triangles (Van Oosterom & Strackee 1983); robust for slightly open meshes.
// O(n) per call: for many queries use TriangleBvh::windingNumber (Utilities/TriangleBvh.h).
Real windingNumber(const TriangleMesh& mesh, const Vector3r& p);

}  // namespace consph
