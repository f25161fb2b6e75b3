// Time per listed neighbour pair of the sums the solvers run over the fluid lists, on one thread,
// and of building those lists (the search, the padded copy): the one-pair-at-a-time forms, the forms over blocks of pairs (Plugins/Pressure/PackedPairSums.h,
// Plugins/Viscosity/ViscosityLaplacian.h; their packing of slots included) and rewrites that were
// tried or replaced. Decisions of a few per cent need this: whole dam-break runs on the shared VM drift by
// 10-20 % between runs, and the VM's clock by a factor two within seconds. Every variant runs
// over the same lists, interleaved, and the fastest of the repetitions counts (use hundreds).
// A checksum (the sum over particles) is printed per variant; the per-particle agreement of the
// block forms with the scalar ones is asserted in tests/unit/test_packed_pair_sums.cpp.
//
//   build-float/bench/pair_loops [particles per side] [repetitions]   (prints a Markdown table)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "Plugins/Pressure/PackedPairSums.h"
#include "Plugins/Pressure/SphPressureTerms.h"
#include "Plugins/Viscosity/ViscosityLaplacian.h"
#include "Simulation/NeighborSearch.h"
#include "Simulation/StepContext.h"
#include "Utilities/Log.h"
#include "Utilities/Timer.h"

#ifdef _OPENMP
#include <omp.h>
#endif

using namespace consph;

namespace {

// Tried for issue 17: the factor m_j W'/r first, then one dot product (two multiplies fewer).
Real rateFactored(const StepContext& ctx, std::size_t i) {
  const FluidView& f = ctx.fluid;
  const NeighborLists& fn = ctx.fluidNeighbors;
  const Vector3r vi = f.velocities[i], xi = f.positions[i];
  Real rate = 0;
  for (Index e = fn.begin(i); e < fn.end(i); ++e) {
    const Index j = fn.indices[e];
    rate += (f.masses[j] * fn.gradFactors[e]) * (vi - f.velocities[j]).dot(xi - f.positions[j]);
  }
  return rate;
}

// The density rate from two slots per pair, (x_j, 0) and (v_j, m_j), as PackedPairSums.h had it
// before it took one (m_j v_j, m_j (x_j - o) . v_j).
Real rateTwoSlots(const PaddedNeighborLists& fn, std::size_t i, const Real* xs, const Real* vs) {
  const Index end = fn.end(i);
#if defined(CONSPH_SIMD_AVX2)
  using L = simd::Lanes<Real>;
  using V = L::V;
  const V xi = L::set1(xs[4 * i]), yi = L::set1(xs[4 * i + 1]), zi = L::set1(xs[4 * i + 2]);
  const V vxi = L::set1(vs[4 * i]), vyi = L::set1(vs[4 * i + 1]), vzi = L::set1(vs[4 * i + 2]);
  V rate = L::zero();
  for (Index e = fn.begin(i); e < end; e += kPairBlock) {
    V x, y, z, unused, vx, vy, vz, m;
    L::transpose(xs, &fn.indices[e], x, y, z, unused);
    L::transpose(vs, &fn.indices[e], vx, vy, vz, m);
    V dot = L::mul(L::sub(xi, x), L::sub(vxi, vx));
    dot = L::fmadd(L::sub(yi, y), L::sub(vyi, vy), dot);
    dot = L::fmadd(L::sub(zi, z), L::sub(vzi, vz), dot);
    rate = L::fmadd(L::mul(m, L::load(&fn.gradFactors[e])), dot, rate);
  }
  return L::sum(rate);
#else
  Real rate = 0;
  for (Index e = fn.begin(i); e < end; ++e) {
    const std::size_t j = 4 * std::size_t(fn.indices[e]);
    Real dot = 0;
    for (int c = 0; c < 3; ++c) dot += (xs[4 * i + c] - xs[j + c]) * (vs[4 * i + c] - vs[j + c]);
    rate += vs[j + 3] * fn.gradFactors[e] * dot;
  }
  return rate;
#endif
}

struct Variant {
  std::string name;
  std::function<double()> pass;  // one pass over all particles; returns a checksum
  double best = 1e30;
  double checksum = 0;
};

}  // namespace

int main(int argc, char** argv) {
  const int side = argc > 1 ? std::atoi(argv[1]) : 40;
  const int repetitions = argc > 2 ? std::atoi(argv[2]) : 300;
  if (side < 4 || side > 200 || repetitions < 1) {
    std::fprintf(stderr, "usage: pair_loops [particles per side 4..200] [repetitions >= 1]\n");
    return 2;
  }
#ifdef _OPENMP
  omp_set_num_threads(1);  // the packing passes and the search too
#endif
  // A block of water at rest spacing 2r with 5 % jitter (r = 0.0125, h = 4r): DamBreak's bulk.
  const Real r = Real(0.0125), spacing = 2 * r, h = 4 * r, rho0 = 1000;
  const CubicSplineKernel kernel(h);
  FluidModel fluid("water", rho0);
  const std::size_t n = std::size_t(side) * side * side;
  fluid.resize(n);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> jitter(-0.05f, 0.05f), speed(-1, 1);
  for (int z = 0, p = 0; z < side; ++z)
    for (int y = 0; y < side; ++y)
      for (int x = 0; x < side; ++x, ++p) {
        fluid.positions[p] = spacing * Vector3r(x + jitter(rng), y + jitter(rng), z + jitter(rng));
        fluid.velocities[p] = Vector3r(speed(rng), speed(rng), speed(rng));
        fluid.masses[p] = rho0 * Real(0.8) * spacing * spacing * spacing;
      }
  {  // Z-order, as the simulation sorts every sortInterval steps
    const std::vector<Index> order = zOrderPermutation(fluid.positions.data(), n, h);
    fluid.fields().permuteSorted(order);
  }
  PointGrid grid;
  grid.build(fluid.positions.data(), n, h);
  NeighborLists fn, bn;
  buildNeighborLists(grid, fluid.positions.data(), n, kernel, true, PairGradients::Factors, fn, fluid.masses.data());
  for (std::size_t i = 0; i < n; ++i) fluid.densities[i] = fn.kernelSums[i];
  bn.offsets.assign(n + 1, 0);
  BoundarySamples samples;
  const LogSink log;
  PaddedNeighborLists padded;
  padded.build(fn);
  StepContext ctx{fluid, samples, fn, padded, bn, kernel, Vector3r(0, -9.81f, 0), r, Real(1e-3), Real(1e-3), Real(1e-3), 0, 0, log};
  std::vector<Real> beta(n), volumes, viscousSlots, fieldSlots;
  for (std::size_t i = 0; i < n; ++i) beta[i] = Real(1e-6) * (1 + Real(i % 7));
  const Real eps = viscosity::regularisation(kernel);

  auto sumOf = [&](auto&& body) {
    double s = 0;
    for (std::size_t i = 0; i < n; ++i) s += double(body(i));
    return s;
  };
  PackedParticles packed;
  packed.packPositions(ctx.fluid);
  std::vector<Vector3r> massGradientSums(n, Vector3r::Zero());  // DFSPH's G_i, from the diagonal's sums once per step
  for (std::size_t i = 0; i < n; ++i) {
    Real squares = 0;
    fluidDiagonalSums(ctx, i, massGradientSums[i], squares);
  }
  std::vector<Real> velocitySlots;
  PointGrid searchGrid;
  NeighborLists searched;
  std::vector<Variant> variants = {
      {"neighbour search: grid, fluid lists with kernel factors and densities (NeighborSearch.cpp)", [&] {
         searchGrid.build(fluid.positions.data(), n, h);
         buildNeighborLists(searchGrid, fluid.positions.data(), n, kernel, true, PairGradients::Factors, searched, fluid.masses.data());
         return sumOf([&](std::size_t i) { return searched.kernelSums[i] + Real(searched.count(i)); });
       }},
      {"neighbour search without the densities' sums and kernel values", [&] {
         searchGrid.build(fluid.positions.data(), n, h);
         buildNeighborLists(searchGrid, fluid.positions.data(), n, kernel, true, PairGradients::Factors, searched);
         return double(searched.pairCount());
       }},
      {"padded copy of the fluid lists (PaddedNeighborLists.h)", [&] {
         padded.build(fn);
         return double(padded.indices.size());
       }},
      {"density rate, scalar (SphPressureTerms.h)", [&] { return sumOf([&](std::size_t i) { return fluidDensityRate(ctx, i); }); }},
      {"density rate, scalar, m_j W'/r first", [&] { return sumOf([&](std::size_t i) { return rateFactored(ctx, i); }); }},
      {"density rate, packed from two slots per pair (x_j; v_j, m_j), with packing the velocities", [&] {
         packSlots(velocitySlots, n, [&](std::size_t j, Real* slot) {
           for (int c = 0; c < 3; ++c) slot[c] = fluid.velocities[j][c];
           slot[3] = fluid.masses[j];
         });
         return sumOf([&](std::size_t i) { return rateTwoSlots(padded, i, packed.positions.data(), velocitySlots.data()); });
       }},
      {"density rate, packed from one slot per pair (PackedPairSums.h), with packing the momenta", [&] {
         packed.packMomenta(ctx.fluid);
         return sumOf([&](std::size_t i) { return packedFluidDensityRate(padded, i, packed, ctx.fluid, massGradientSums[i]); });
       }},
      {"pressure acceleration, scalar (SphPressureTerms.h)",
       [&] { return sumOf([&](std::size_t i) { return fluidPressureAcceleration(ctx, i, beta).sum(); }); }},
      {"pressure acceleration, packed (PackedPairSums.h), with packing m_j beta_j",
       [&] {
         packed.packPressures(ctx.fluid, beta.data());
         return sumOf([&](std::size_t i) { return packedFluidPressureAcceleration(padded, i, packed, beta[i], massGradientSums[i]).sum(); });
       }},
      {"viscous sum and rate, scalar (ViscosityLaplacian.h)", [&] {
         viscosity::fluidVolumes(ctx.fluid, volumes);
         return sumOf([&](std::size_t i) {
           Real rate[6] = {0, 0, 0, 0, 0, 0};
           return viscosity::fluidSumWithRate(ctx.fluid, fn, i, volumes.data(), eps, rate).sum() + rate[0];
         });
       }},
      {"viscous sum and rate, packed (ViscosityLaplacian.h), with packing", [&] {
         packSlots(viscousSlots, n, [&](std::size_t j, Real* slot) {
           for (int c = 0; c < 3; ++c) slot[c] = fluid.positions[j][c];
           slot[3] = fluid.masses[j] / fluid.densities[j];
         });
         packSlots(velocitySlots, n, [&](std::size_t j, Real* slot) {
           for (int c = 0; c < 3; ++c) slot[c] = fluid.velocities[j][c];
           slot[3] = fluid.masses[j];
         });
         return sumOf([&](std::size_t i) {
           Real rate[6] = {0, 0, 0, 0, 0, 0};
           return viscosity::packedFluidSumWithRate(padded, i, viscousSlots.data(), velocitySlots.data(), eps, rate).sum() + rate[0];
         });
       }},
      {"viscous sum of a field (Weiler 2018's operator), scalar", [&] {
         viscosity::fluidVolumes(ctx.fluid, volumes);
         return sumOf([&](std::size_t i) { return viscosity::fluidSum(ctx.fluid, fn, i, fluid.velocities.data(), volumes.data(), eps).sum(); });
       }},
      {"viscous sum of a field, packed (ViscosityLaplacian.h), with packing the field", [&] {
         packSlots(viscousSlots, n, [&](std::size_t j, Real* slot) {
           for (int c = 0; c < 3; ++c) slot[c] = fluid.positions[j][c];
           slot[3] = fluid.masses[j] / fluid.densities[j];
         });
         packSlots(fieldSlots, n, [&](std::size_t j, Real* slot) {
           for (int c = 0; c < 3; ++c) slot[c] = fluid.velocities[j][c];
           slot[3] = 0;
         });
         return sumOf([&](std::size_t i) { return viscosity::packedFluidSum(padded, i, viscousSlots.data(), fieldSlots.data(), eps).sum(); });
       }},
  };
  for (int rep = 0; rep < repetitions; ++rep)
    for (Variant& v : variants) {
      const Timer t;
      v.checksum = v.pass();
      v.best = std::min(v.best, t.seconds());
    }
  const double pairs = double(fn.pairCount());
  std::printf("%zu particles, %.1f fluid neighbours each, one thread, %s, fastest of %d\n\n", n, pairs / double(n),
              sizeof(Real) == 4 ? "float" : "double", repetitions);
  std::printf("| loop | ns per pair | checksum |\n|---|---|---|\n");
  for (const Variant& v : variants) std::printf("| %s | %.2f | %.6g |\n", v.name.c_str(), v.best / pairs * 1e9, v.checksum);
  return 0;
}
