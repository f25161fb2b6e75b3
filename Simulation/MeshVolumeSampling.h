// A fluid that starts as the volume of a closed mesh (fluids[].meshVolumes): lattice points of
// the mesh's bounding box that lie inside it (winding number > 1/2, so a mesh with small holes
// still has an inside). Two lattices: consph's cell-centred one of spacing d, starting d/2 in
// from the box's corner, and SPlisHSPlasH's for its FluidModels (denseMode 0): the centres of a
// 2r voxel grid from the box's corner, as many as fit with the last voxel starting inside.
#pragma once
#include <vector>

#include "Simulation/FluidBlock.h"
#include "Utilities/TriangleMesh.h"

namespace consph {

// `lattice`: BlockLattice::CellCentred or BlockLattice::SplishSplashRegular.
std::vector<Vector3r> sampleMeshVolume(const TriangleMesh& closedMesh, BlockLattice lattice, Real spacing, Real radius);

}  // namespace consph
