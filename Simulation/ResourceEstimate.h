// What a scene will allocate, estimated in floating point before anything is built: fluid
// particles (blocks and emitter budgets), boundary samples or volume-map cells, and memory. A
// request that cannot fit (1e9 particles, r = 1e-5 in a 1 m box) is refused up front with the
// estimate, instead of growing for minutes and dying of bad_alloc; and no lattice count is
// converted to an integer before it is known to fit (a "max": [1e12, ...] block overflowed int
// and silently ran one layer of 169 particles).
#pragma once
#include <array>
#include <string>

#include "Simulation/Common.h"
#include "Simulation/FluidBlock.h"

namespace consph {

// Memory of one fluid particle with its fields and neighbour lists. Measured: DamBreak at
// r = 0.01 m against r = 0.02 m, 131 k more fluid particles and 337 k more boundary samples,
// 292 MB more peak memory: ~1.7 KB per fluid particle at ~200 B per boundary sample.
inline constexpr double kBytesPerFluidParticle = 2000;
inline constexpr double kBytesPerBoundarySample = 250;

struct BoundaryEstimate {
  double samples = 0;  // boundary particles (before thinning)
  double cells = 0;    // volume-map grid nodes
  double bytes = 0;
};

struct ResourceEstimate {
  double fluidParticles = 0;
  BoundaryEstimate boundary;
  double bytes() const { return fluidParticles * kBytesPerFluidParticle + boundary.bytes; }
};

// The default of simulation.maxParticles: half this machine's physical memory, in fluid particles
// of kBytesPerFluidParticle.
double defaultMaxParticles();

// Throws InputError with the estimate when it needs more memory than `maxParticles` fluid
// particles would (0: defaultMaxParticles()), or more particles, samples or cells than a 32-bit
// index holds.
void refuseIfTooLarge(const ResourceEstimate& estimate, double maxParticles);

// A lattice count known to fit an int, for the sampling code; throws InputError naming `what`
// otherwise (the estimate refuses such scenes first; this guards other callers).
int checkedCount(double count, const std::string& what);

}  // namespace consph
