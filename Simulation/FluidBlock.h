// A box of fluid and the lattice its particles start on. consph's own lattice is cell-centred
// with the particle spacing d (volume d^3 each); SPlisHSPlasH's three "denseMode" lattices are
// reproduced as they are so that an imported scene starts with the same particles (its regular
// one is a 2r grid whose particles carry the volume 0.8 (2r)^3, 20 % under-dense at the start).
#pragma once
#include <array>
#include <vector>

#include "Simulation/Common.h"

namespace consph {

enum class BlockLattice {
  CellCentred,            // consph: spacing d, cell-centred from min
  SplishSplashRegular,    // SPlisHSPlasH denseMode 0: cubic, spacing 2r, 2r in from min
  SplishSplashMoreDense,  // denseMode 1: layers sqrt(3) r apart, alternately shifted by r in z and x
  SplishSplashDense,      // denseMode 2: columns 2 sqrt(6)/3 (2r) apart, staggered (close packing)
};

// The scene names ("cellCentred", "splishsplashRegular", ...), in the enum's order.
const std::vector<const char*>& blockLatticeNames();
BlockLattice blockLatticeFromName(const std::string& name);  // a name of blockLatticeNames()

struct FluidBlock {
  Vector3r min, max;  // m
  Vector3r velocity;  // initial velocity, m/s
  BlockLattice lattice = BlockLattice::CellCentred;
};

// Particles per axis of a cell-centred block of spacing d (at least 1), in floating point.
std::array<double, 3> latticeCounts(const FluidBlock& block, Real spacing);

// Particles per axis of `block` on its lattice (`spacing` d: the cell-centred one's, `radius` r:
// SPlisHSPlasH's), in floating point; a SPlisHSPlasH block of 1 particle or less across any axis
// is empty (0 on every axis), as SPlisHSPlasH skips it.
std::array<double, 3> blockCounts(const FluidBlock& block, Real spacing, Real radius);

// Appends the positions of `block`'s particles (blockCounts of them) to `positions`. The counts
// must have been checked to fit (refuseIfTooLarge).
void sampleBlock(const FluidBlock& block, Real spacing, Real radius, std::vector<Vector3r>& positions);

}  // namespace consph
