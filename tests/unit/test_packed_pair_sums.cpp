// The sums over blocks of pairs (Plugins/Pressure/PackedPairSums.h, the viscous sum of
// Plugins/Viscosity/ViscosityLaplacian.h) against their one-pair-at-a-time forms, on every particle
// of a jittered block with random velocities and pressures: equal up to the round-off of another
// summation order. And the padded lists (Simulation/PaddedNeighborLists.h) keep every listed
// pair, in order.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "Plugins/Pressure/PackedPairSums.h"
#include "Plugins/Pressure/SphPressureTerms.h"
#include "Plugins/Viscosity/ViscosityLaplacian.h"
#include "TestUtil.h"
#include "support/StandaloneStep.h"

using namespace consph;

namespace {

// A 9 x 8 x 7 block at spacing 2r with 10 % jitter, plus one particle far away (an empty row):
// rows of every length from a corner's few pairs to the bulk's 30-odd, so every remainder mod
// the block size occurs.
constexpr Real kRadius = Real(0.01);
void fillJitteredBlock(test::StandaloneStep& s, unsigned seed) {
  const Real r = kRadius;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.1, 0.1), speed(-2, 2), pressure(0, 3e-6);
  const int nx = 9, ny = 8, nz = 7;
  s.fluid.resize(nx * ny * nz + 1);
  for (int z = 0, p = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x, ++p)
        s.fluid.positions[p] = 2 * r * Vector3r(Real(x + jitter(rng)), Real(y + jitter(rng)), Real(z + jitter(rng)));
  s.fluid.positions.back() = Vector3r(1, 1, 1);
  for (std::size_t i = 0; i < s.fluid.size(); ++i) {
    s.fluid.velocities[i] = Vector3r(Real(speed(rng)), Real(speed(rng)), Real(speed(rng)));
    // Masses that differ per particle, so that a mixed-up lane would show.
    s.fluid.masses[i] = Real(1000 * 8 * r * r * r * (0.9 + 0.2 * (double(i % 11) / 10)));
    s.fluid.pressures[i] = Real(pressure(rng));
  }
  s.update();
}

}  // namespace

TEST(PackedPairSums, PaddedListsKeepEveryPairInOrder) {
  test::StandaloneStep s(kRadius, 1000);
  fillJitteredBlock(s, 1);
  const NeighborLists& fn = s.fluidNeighbors;
  const PaddedNeighborLists& padded = s.paddedFluidNeighbors;
  ASSERT_EQ(padded.offsets.size(), fn.offsets.size());
  std::size_t remainders[kPairBlock] = {};
  for (std::size_t i = 0; i < s.fluid.size(); ++i) {
    const Index begin = padded.offsets[i], end = padded.offsets[i + 1];
    ASSERT_EQ((end - begin) % kPairBlock, 0u) << "row " << i;
    ASSERT_GE(end - begin, fn.count(i));
    ASSERT_LT(end - begin, fn.count(i) + kPairBlock);
    ++remainders[fn.count(i) % kPairBlock];
    for (Index k = 0; k < end - begin; ++k) {
      if (k < fn.count(i)) {
        EXPECT_EQ(padded.indices[begin + k], fn.indices[fn.begin(i) + k]);
        EXPECT_EQ(padded.gradFactors[begin + k], fn.gradFactors[fn.begin(i) + k]);
      } else {
        EXPECT_EQ(padded.indices[begin + k], Index(i));
        EXPECT_EQ(padded.gradFactors[begin + k], Real(0));
      }
    }
  }
  EXPECT_EQ(fn.count(s.fluid.size() - 1), 0u);  // the particle far away: an empty row
  for (Index r = 0; r < kPairBlock; ++r) EXPECT_GT(remainders[r], 0u) << "no row of length " << r << " mod " << kPairBlock;
}

TEST(PackedPairSums, EqualTheScalarSumsOnEveryParticle) {
  // Near the scene's origin at rest on average, and far from it (60 m) drifting at 13 m/s: the
  // density rate's one-slot form takes positions from the block's centre, so its round-off must not
  // grow with the distance to the origin, and it is bounded by its terms' magnitudes under a drift.
  struct Placement {
    Vector3r shift, drift;
  };
  const Placement placements[] = {{Vector3r::Zero(), Vector3r::Zero()}, {Vector3r(40, -25, 60), Vector3r(12, 0, -5)}};
  for (const Placement& placement : placements) {
    SCOPED_TRACE("block shifted by " + std::to_string(placement.shift.norm()) + " m, drifting at " +
                 std::to_string(placement.drift.norm()) + " m/s");
    test::StandaloneStep s(kRadius, 1000);
    fillJitteredBlock(s, 2);
    for (std::size_t i = 0; i < s.fluid.size(); ++i) s.fluid.positions[i] += placement.shift, s.fluid.velocities[i] += placement.drift;
    s.update();
    const StepContext ctx = s.context(Real(1e-3));
    const PaddedNeighborLists& padded = ctx.paddedFluidNeighbors;
    PackedParticles packed;
    packed.packPositions(ctx.fluid);
    packed.packMomenta(ctx.fluid);
    std::vector<Real> beta(s.fluid.pressures.begin(), s.fluid.pressures.end());
    packed.packPressures(ctx.fluid, beta.data());
    // Round-off bound: the sum of the terms' magnitudes times a few units of round-off.
    const double unit = test::roundoff(1e-14, 2e-6);
    double worstRate = 0, worstAcceleration = 0, worstRatePairScale = 0;
    for (std::size_t i = 0; i < s.fluid.size(); ++i) {
      const FluidView& f = ctx.fluid;
      const NeighborLists& fn = ctx.fluidNeighbors;
      // The packed density rate sums v_i . G_i, (x_i - o) . sum_j f_ij m_j v_j and
      // sum_j f_ij m_j (x_j - o) . v_j (o: the block's centre), whose terms are larger than the pair
      // form's: its round-off scale is theirs.
      double rateScale = 0, oneSlotScale = 0, accelerationScale = 0;
      for (Index e = fn.begin(i); e < fn.end(i); ++e) {
        const Index j = fn.indices[e];
        const Vector3r xij = f.positions[i] - f.positions[j], g = fn.gradient(e, xij);
        rateScale += std::abs(double(f.masses[j] * (f.velocities[i] - f.velocities[j]).dot(g)));
        const double factor = std::abs(double(fn.gradFactors[e] * f.masses[j]));
        const Vector3r xi = f.positions[i] - packed.origin, xj = f.positions[j] - packed.origin;
        oneSlotScale += factor * (std::abs(double(xij.dot(f.velocities[i]))) + std::abs(double(xi.dot(f.velocities[j]))) +
                                  std::abs(double(xj.dot(f.velocities[j]))));
        accelerationScale += double(f.masses[j] * (beta[i] + beta[j]) * g.norm());
      }
      Vector3r massGradientSum = Vector3r::Zero();
      Real squares = 0;
      fluidDiagonalSums(ctx, i, massGradientSum, squares);
      const Real scalarRate = fluidDensityRate(ctx, i);
      const Real packedRate = packedFluidDensityRate(padded, i, packed, ctx.fluid, massGradientSum);
      const Vector3r scalarAcceleration = fluidPressureAcceleration(ctx, i, beta);
      const Vector3r packedAcceleration = packedFluidPressureAcceleration(padded, i, packed, beta[i], massGradientSum);
      if (fn.count(i) == 0) {
        EXPECT_EQ(packedRate, Real(0));
        EXPECT_EQ(packedAcceleration, Vector3r::Zero());
        continue;
      }
      const double rateError = std::abs(double(packedRate - scalarRate)) / (rateScale + oneSlotScale);
      const double accelerationError = double((packedAcceleration - scalarAcceleration).norm()) / accelerationScale;
      EXPECT_LE(rateError, unit) << "particle " << i << ": " << packedRate << " vs " << scalarRate;
      EXPECT_LE(accelerationError, unit) << "particle " << i;
      worstRate = std::max(worstRate, rateError);
      worstRatePairScale = std::max(worstRatePairScale, std::abs(double(packedRate - scalarRate)) / rateScale);
      worstAcceleration = std::max(worstAcceleration, accelerationError);
    }
    std::printf("largest differences, relative to the sums of the terms' magnitudes: density rate %.2e (%.2e of the pair "
                "form's terms), pressure %.2e\n",
                worstRate, worstRatePairScale, worstAcceleration);
  }
}

TEST(PackedPairSums, ViscousSumsEqualTheScalarOnEveryParticle) {
  test::StandaloneStep s(kRadius, 1000);
  fillJitteredBlock(s, 3);
  const StepContext ctx = s.context(Real(1e-3));
  const FluidView& f = ctx.fluid;
  const NeighborLists& fn = ctx.fluidNeighbors;
  const Real eps = viscosity::regularisation(ctx.kernel);
  std::vector<Real> volumes, positionsVolumes, velocities;
  viscosity::fluidVolumes(f, volumes);
  packSlots(positionsVolumes, f.size(), [&](std::size_t j, Real* slot) {
    for (int c = 0; c < 3; ++c) slot[c] = f.positions[j][c];
    slot[3] = f.masses[j] / f.densities[j];
  });
  packSlots(velocities, f.size(), [&](std::size_t j, Real* slot) {
    for (int c = 0; c < 3; ++c) slot[c] = f.velocities[j][c];
    slot[3] = 0;
  });
  const double unit = test::roundoff(1e-14, 2e-6);
  double worstSum = 0, worstRate = 0;
  for (std::size_t i = 0; i < f.size(); ++i) {
    // The magnitudes of the terms: the round-off scale of each sum.
    double sumScale = 0, rateScale = 0;
    for (Index e = fn.begin(i); e < fn.end(i); ++e) {
      const Index j = fn.indices[e];
      const Vector3r xij = f.positions[i] - f.positions[j];
      const double weight = double(volumes[j] / (xij.squaredNorm() + eps));
      const double gradient = double(fn.gradient(e, xij).norm());
      sumScale += weight * std::abs(double((f.velocities[i] - f.velocities[j]).dot(xij))) * gradient;
      rateScale += weight * double(xij.norm()) * gradient;
    }
    Real scalarRate[6] = {0, 0, 0, 0, 0, 0}, packedRate[6] = {0, 0, 0, 0, 0, 0};
    const Vector3r scalarSum = viscosity::fluidSumWithRate(f, fn, i, volumes.data(), eps, scalarRate);
    const Vector3r packedSum =
        viscosity::packedFluidSumWithRate(ctx.paddedFluidNeighbors, i, positionsVolumes.data(), velocities.data(), eps, packedRate);
    if (fn.count(i) == 0) {
      EXPECT_EQ(packedSum, Vector3r::Zero());
      EXPECT_EQ(viscosity::packedFluidSum(ctx.paddedFluidNeighbors, i, positionsVolumes.data(), velocities.data(), eps), Vector3r::Zero());
      for (Real r : packedRate) EXPECT_EQ(r, Real(0));
      continue;
    }
    const double sumError = double((packedSum - scalarSum).norm()) / sumScale;
    EXPECT_LE(sumError, unit) << "particle " << i;
    worstSum = std::max(worstSum, sumError);
    // Weiler 2018's operator: the same sum of any field, here the velocities again.
    const Vector3r fieldSum = viscosity::packedFluidSum(ctx.paddedFluidNeighbors, i, positionsVolumes.data(), velocities.data(), eps);
    const double fieldError = double((fieldSum - viscosity::fluidSum(f, fn, i, f.velocities.data(), volumes.data(), eps)).norm()) / sumScale;
    EXPECT_LE(fieldError, unit) << "particle " << i;
    worstSum = std::max(worstSum, fieldError);
    for (int c = 0; c < 6; ++c) {
      const double rateError = std::abs(double(packedRate[c] - scalarRate[c])) / rateScale;
      EXPECT_LE(rateError, unit) << "particle " << i << ", entry " << c;
      worstRate = std::max(worstRate, rateError);
    }
  }
  std::printf("largest differences, relative to the sums of the terms' magnitudes: viscous sums %.2e, the rate %.2e\n", worstSum,
              worstRate);
}
