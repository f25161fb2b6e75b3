// DFSPH's density solve stops when the average predicted compression is within maxError; with
// maxErrorParticle (default 1 % of rho0) it goes on until every particle's is within that too.
// Under the average alone a few volume-map corner particles kept 1-2.5 rho0 for 0.2 s and passed
// through the wall (bench/RESULTS.md, issue 15). Here one particle of a resting block is pushed
// 0.6 r towards its neighbour: its compression is far above 1 %, the block's average is not.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "Plugins/Pressure/DFSPH.h"
#include "tests/support/StandaloneStep.h"

using namespace consph;

namespace {

constexpr Real kRadius = Real(0.025), kRho0 = 1000, kDt = Real(0.002);
constexpr int kSide = 10;

void makeBlockWithOneSqueezedParticle(test::StandaloneStep& s) {
  const Real d = 2 * kRadius;
  FluidModel& f = s.fluid;
  f.resize(std::size_t(kSide * kSide * kSide));
  std::size_t p = 0;
  for (int i = 0; i < kSide; ++i)
    for (int j = 0; j < kSide; ++j)
      for (int k = 0; k < kSide; ++k, ++p) {
        f.positions[p] = Vector3r(i * d, j * d, k * d);
        f.velocities[p] = Vector3r::Zero();
        f.masses[p] = kRho0 * d * d * d;
        f.ids[p] = Index(p);
      }
  // The particle at (5, 5, 5) moved 0.6 r towards (4, 5, 5).
  f.positions[(5 * kSide + 5) * kSide + 5][0] -= Real(0.6) * kRadius;
  s.update();
}

struct Outcome {
  Real largestPredicted;  // max_i (rho*_i - rho0) / rho0 after the solve, computed here
  Real averagePredicted;  // the mean of max(rho*_i - rho0, 0) / rho0
  Real largestReported;   // the solver's stats
  int iterations;
};

// One density solve with maxErrorParticle `percent`; the predicted densities after it,
// rho*_i = rho_i + dt sum_j m_j (v_i - v_j) . grad W_ij (Eq. 6), are recomputed from the
// velocities the solve leaves.
Outcome solveWith(double percent) {
  test::StandaloneStep s(kRadius, kRho0);
  makeBlockWithOneSqueezedParticle(s);
  // The average criterion at 0.5 %, met by the block before any iteration; no divergence solve,
  // no warm start, and the target rho0 for every particle (no overlap relief, no relaxation).
  DFSPH dfsph(Params(json{{"maxError", 0.5}, {"maxErrorParticle", percent}, {"minIterations", 0}, {"maxIterations", 500},
                          {"enableDivergenceSolver", false}, {"warmStart", false}, {"overlapReliefSpeed", 0},
                          {"densityRelaxation", "step"}},
                     "pressureSolver", DFSPH::parameters(), s.log),
              s.fluid);
  StepContext ctx = s.context(kDt);
  dfsph.beforeNonPressureForces(ctx);
  dfsph.solve(ctx);
  const FluidModel& f = s.fluid;
  const NeighborLists& nl = s.fluidNeighbors;
  Outcome o{0, 0, dfsph.stats().largestDensityError, dfsph.stats().pressureIterations};
  for (std::size_t i = 0; i < f.size(); ++i) {
    Real rho = f.densities[i];
    for (Index e = nl.begin(i); e < nl.end(i); ++e)
      rho += kDt * f.masses[nl.indices[e]] * (f.velocities[i] - f.velocities[nl.indices[e]]).dot(nl.gradient(e, f.positions[i] - f.positions[nl.indices[e]]));
    const Real error = (rho - kRho0) / kRho0;
    o.largestPredicted = std::max(o.largestPredicted, error);
    o.averagePredicted += std::max(error, Real(0)) / Real(f.size());
  }
  std::printf("[ particle error ] maxErrorParticle %g %%: %d iterations, largest %.3f %% (reported %.3f %%), average %.4f %%\n",
              percent, o.iterations, 100 * double(o.largestPredicted), 100 * double(o.largestReported), 100 * double(o.averagePredicted));
  return o;
}

}  // namespace

TEST(DFSPHParticleError, EveryParticleIsHeldWithinMaxErrorParticle) {
  const Outcome averageOnly = solveWith(0);
  const Outcome held = solveWith(1);
  // Not vacuous: under the average alone the squeezed particle stays far above 1 %.
  EXPECT_EQ(averageOnly.iterations, 0);
  EXPECT_GT(averageOnly.largestPredicted, Real(0.05));
  EXPECT_LT(averageOnly.averagePredicted, Real(0.005));
  // With the criterion every particle's predicted compression is within 1 % (the reported value
  // is the one recomputed here, to round-off).
  EXPECT_GT(held.iterations, 0);
  EXPECT_LE(held.largestPredicted, Real(0.01));
  EXPECT_NEAR(held.largestReported, held.largestPredicted, Real(1e-4));
}
