// BoundaryPressureTreatment on hand-made particle sets: the MLS extrapolation of Band et al. 2018
// reproduces linear pressure fields, clamps at 0, and falls back to the weighted average when the
// moment matrix is singular; the three treatments' boundary accelerations follow Eqs. (16), (33).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "Plugins/Pressure/BoundaryPressureTreatment.h"
#include "tests/TestUtil.h"
#include "tests/support/StandaloneStep.h"

using namespace consph;

namespace {

constexpr Real kRadius = Real(0.025), kRho0 = 1000;

// A flat wall of boundary samples in the plane y = 0 (spacing r) under a fluid lattice (spacing
// 2r) whose lowest layer is at y = firstLayer.
void makeWall(test::StandaloneStep& s, int fluidLayers, Real firstLayer) {
  const int n = 12;
  for (int i = -n; i <= n; ++i)
    for (int k = -n; k <= n; ++k) {
      s.boundary.positions.push_back(Vector3r(i * kRadius, 0, k * kRadius));
      s.boundary.velocities.push_back(Vector3r::Zero());
      s.boundary.masses.push_back(Real(0.5) * kRho0 * kRadius * kRadius * kRadius);
      s.boundary.bodies.push_back(0);
    }
  std::vector<Vector3r> x;
  for (int i = -4; i <= 4; ++i)
    for (int j = 0; j < fluidLayers; ++j)
      for (int k = -4; k <= 4; ++k) x.push_back(Vector3r(2 * i * kRadius, firstLayer + 2 * j * kRadius, 2 * k * kRadius));
  s.fluid.resize(x.size());
  for (std::size_t p = 0; p < x.size(); ++p) {
    s.fluid.positions[p] = x[p];
    s.fluid.masses[p] = kRho0 * 8 * kRadius * kRadius * kRadius;
  }
  s.update();
}

}  // namespace

TEST(BoundaryPressureTreatment, ExtrapolationReproducesALinearPressureField) {
  test::StandaloneStep s(kRadius, kRho0);
  // Layers at r and 3r: two layers inside the support radius 4r of the wall samples.
  makeWall(s, 4, kRadius);
  BoundaryPressureTreatment t(BoundaryPressure::Extrapolation);
  const StepContext ctx = s.context(Real(0.001));
  t.beginStep(ctx);
  ASSERT_TRUE(t.extrapolates());
  // Hydrostatic-like field p = 5000 - 20000 y + 3000 x: positive at the wall, so no clamping.
  auto field = [](const Vector3r& x) { return Real(5000) - Real(20000) * x[1] + Real(3000) * x[0]; };
  t.extrapolate([&](Index j) { return field(s.fluid.positions[j]); });
  std::size_t checked = 0;
  for (std::size_t k = 0; k < s.boundary.size(); ++k) {
    const Vector3r& xk = s.boundary.positions[k];
    // Samples with a full 3D fluid neighbourhood (inside the fluid's footprint): exact for linear fields.
    if (std::abs(xk[0]) > 4 * kRadius || std::abs(xk[2]) > 4 * kRadius) continue;
    // Float: a weighted least-squares fit, sums of ~30 neighbour terms rounded to eps each, then
    // a 4 x 4 solve extrapolating 1-3 r outside the fluid, which amplifies them about 4 times:
    // ~30 x 4 eps (measured up to 34 eps).
    EXPECT_NEAR(t.boundaryPressures()[k], field(xk), test::roundoff(1e-6, 128 * test::kFloatEps) * field(xk)) << "sample " << k;
    ++checked;
  }
  EXPECT_GT(checked, 50u);  // (samples beyond the fluid's edge may fall back; they are not checked)
}

TEST(BoundaryPressureTreatment, ExtrapolationClampsNegativePressuresAtZero) {
  test::StandaloneStep s(kRadius, kRho0);
  makeWall(s, 4, kRadius);
  BoundaryPressureTreatment t(BoundaryPressure::Extrapolation);
  const StepContext ctx = s.context(Real(0.001));
  t.beginStep(ctx);
  // Pressure rising with height: the linear fit is negative at the wall.
  t.extrapolate([&](Index j) { return Real(50000) * s.fluid.positions[j][1]; });
  for (std::size_t k = 0; k < s.boundary.size(); ++k) EXPECT_GE(t.boundaryPressures()[k], 0);
}

TEST(BoundaryPressureTreatment, ExtrapolationWithASingleFluidNeighbourFallsBackToItsPressure) {
  // One fluid particle above one boundary sample: the moment matrix is zero (singular).
  test::StandaloneStep s(kRadius, kRho0);
  s.boundary.resize(1);
  s.boundary.masses[0] = Real(0.5) * kRho0 * kRadius * kRadius * kRadius;
  s.fluid.resize(1);
  s.fluid.positions[0] = Vector3r(0, 2 * kRadius, 0);
  s.fluid.masses[0] = kRho0 * 8 * kRadius * kRadius * kRadius;
  s.update();
  ASSERT_EQ(s.boundaryNeighbors.count(0), 1u);
  BoundaryPressureTreatment t(BoundaryPressure::Extrapolation);
  StepContext ctx = s.context(Real(0.001));
  t.beginStep(ctx);
  t.extrapolate([](Index) { return Real(1234.5); });
  EXPECT_EQ(t.fallbackCount(), 1u);
  ASSERT_TRUE(std::isfinite(t.boundaryPressures()[0]));
  EXPECT_NEAR(t.boundaryPressures()[0], Real(1234.5), Real(1e-9) * 1234.5);
  // And the boundary acceleration it produces is finite and pushes the particle away from the wall.
  const Real p = Real(1234.5), beta = p / (s.fluid.densities[0] * s.fluid.densities[0]);
  const Vector3r a = t.acceleration(ctx, 0, beta, p, t.boundaryPressures());
  EXPECT_TRUE(a.allFinite());
  EXPECT_GT(a[1], 0);
}

TEST(BoundaryPressureTreatment, ExtrapolationOfAFlatFluidLayerFallsBackToTheWeightedAverage) {
  // Fluid at rest sits about 2r above Akinci wall samples, so with h = 4r the samples see one
  // fluid layer: no slope along the wall normal can be fitted (rank-2 moment matrix).
  test::StandaloneStep s(kRadius, kRho0);
  makeWall(s, 3, 2 * kRadius);
  BoundaryPressureTreatment t(BoundaryPressure::Extrapolation);
  const StepContext ctx = s.context(Real(0.001));
  t.beginStep(ctx);
  t.extrapolate([&](Index j) { return Real(100) + Real(1000) * s.fluid.positions[j][0]; });
  std::vector<bool> seen(s.boundary.size(), false);
  for (Index k : s.boundaryNeighbors.indices) seen[k] = true;
  const std::size_t withFluid = std::size_t(std::count(seen.begin(), seen.end(), true));
  for (std::size_t k = 0; k < s.boundary.size(); ++k) EXPECT_TRUE(std::isfinite(t.boundaryPressures()[k]));
  ASSERT_GT(withFluid, 0u);
  EXPECT_EQ(t.fallbackCount(), withFluid);
}

TEST(BoundaryPressureTreatment, BoundaryAccelerationsFollowEqs16And33) {
  test::StandaloneStep s(kRadius, kRho0);
  makeWall(s, 3, 2 * kRadius);
  std::size_t i = 0;  // the centre particle of the bottom layer
  for (std::size_t q = 0; q < s.fluid.size(); ++q)
    if ((s.fluid.positions[q] - Vector3r(0, 2 * kRadius, 0)).norm() < 1e-9) i = q;
  ASSERT_NEAR(s.fluid.positions[i][1], 2 * kRadius, 1e-12);
  const Real p = 2000, rho = s.fluid.densities[i], beta = p / (rho * rho);
  // Eq. (16) / (33) summed directly over the boundary neighbours.
  Vector3r g = Vector3r::Zero();
  for (Index e = s.boundaryNeighbors.begin(i); e < s.boundaryNeighbors.end(i); ++e)
    g += s.boundary.masses[s.boundaryNeighbors.indices[e]] * s.boundaryNeighbors.gradW[e];
  ASSERT_GT(g.norm(), 0);
  BoundaryPressureTreatment consistent(BoundaryPressure::Consistent), mirroring(BoundaryPressure::Mirroring);
  consistent.beginStep(s.context(Real(0.001)));
  mirroring.beginStep(s.context(Real(0.001)));
  const StepContext ctx = s.context(Real(0.001));
  const std::vector<Real> none;
  EXPECT_LT((consistent.acceleration(ctx, i, beta, p, none) + beta * g).norm(), 1e-12 * (beta * g).norm());
  const Vector3r mirrored = -(beta + p / (kRho0 * kRho0)) * g;
  EXPECT_LT((mirroring.acceleration(ctx, i, beta, p, none) - mirrored).norm(), 1e-12 * mirrored.norm());
  // Eq. (15)'s extra diagonal term only for the classical treatments.
  EXPECT_EQ(consistent.diagonalTerm(i), 0);
  EXPECT_GT(mirroring.diagonalTerm(i), 0);
}

// Eq. (14)'s boundary part of the density rate, sum_k m~_k (v_i - v_k) . grad W_ik, from the
// step's sums (v_i . g_i minus the samples' own part) as the pairs give it, for every fluid
// particle over a wall: at rest, and sliding and rising under the fluid.
TEST(BoundaryPressureTreatment, DensityRateFromTheStepsSumsIsEq14sBoundarySum) {
  for (const Vector3r& wallVelocity : {Vector3r(0, 0, 0), Vector3r(Real(0.7), Real(0.3), Real(-0.2))}) {
    test::StandaloneStep s(kRadius, kRho0);
    makeWall(s, 3, 2 * kRadius);
    for (auto& v : s.boundary.velocities) v = wallVelocity;
    for (std::size_t i = 0; i < s.fluid.size(); ++i)
      s.fluid.velocities[i] = Vector3r(Real(0.1) * Real(i % 7), -Real(0.5) + Real(0.05) * Real(i % 5), Real(0.02) * Real(i % 3));
    BoundaryPressureTreatment t(BoundaryPressure::Consistent);
    t.keepSampleFlux();
    const StepContext ctx = s.context(Real(0.001));
    t.beginStep(ctx);
    std::size_t withWall = 0;
    for (std::size_t i = 0; i < s.fluid.size(); ++i) {
      Real pairs = 0, scale = 0;
      for (Index e = s.boundaryNeighbors.begin(i); e < s.boundaryNeighbors.end(i); ++e) {
        const Index k = s.boundaryNeighbors.indices[e];
        const Real term = s.boundary.masses[k] * (s.fluid.velocities[i] - s.boundary.velocities[k]).dot(s.boundaryNeighbors.gradW[e]);
        pairs += term;
        scale += std::abs(term);
      }
      withWall += scale > 0;
      EXPECT_NEAR(t.densityRate(i, s.fluid.velocities[i]), pairs, 1e-5 * scale) << "particle " << i;
    }
    EXPECT_GT(withWall, s.fluid.size() / 4);
  }
}

// A thin cloud of fluid over a sample (a few particles left in a corner: not singular, but its
// fit amplifies the pressures' spread hundreds of times) has its slope scaled down to
// kMaxSlopeAmplification: p_k stays within that many spreads of the weighted average, where the
// raw fit was far outside. A regular two-layer wall (21, the test above) is not touched.
TEST(BoundaryPressureTreatment, ExtrapolationCapsTheSlopeOfAThinCloud) {
  test::StandaloneStep s(kRadius, kRho0);
  s.boundary.resize(1);
  s.boundary.masses[0] = Real(0.5) * kRho0 * kRadius * kRadius * kRadius;
  // Four particles in a square 3 r above the sample and one 0.5 r above its centre: smallest /
  // largest moment eigenvalue 0.022 (not singular), amplification 68 (numpy, 2026-12-02).
  const std::vector<Vector3r> x = {Vector3r(-kRadius, 3 * kRadius, -kRadius), Vector3r(kRadius, 3 * kRadius, -kRadius),
                                   Vector3r(-kRadius, 3 * kRadius, kRadius), Vector3r(kRadius, 3 * kRadius, kRadius),
                                   Vector3r(0, Real(3.5) * kRadius, 0)};
  s.fluid.resize(x.size());
  for (std::size_t p = 0; p < x.size(); ++p) {
    s.fluid.positions[p] = x[p];
    s.fluid.masses[p] = kRho0 * 8 * kRadius * kRadius * kRadius;
  }
  s.update();
  ASSERT_EQ(s.boundaryNeighbors.pairCount(), x.size());
  BoundaryPressureTreatment t(BoundaryPressure::Extrapolation);
  const StepContext ctx = s.context(Real(0.001));
  t.beginStep(ctx);
  // Pressures 1000 to 1010 Pa, rising with height (the fit alone: about 1000 - 68 x 10 Pa).
  auto pressure = [&](Index j) { return Real(1000) + Real(10) * (s.fluid.positions[j][1] - 3 * kRadius) / (Real(0.5) * kRadius); };
  t.extrapolate(pressure);
  EXPECT_EQ(t.fallbackCount(), 0u);
  EXPECT_EQ(t.limitedSlopeCount(), 1u);
  const Real pk = t.boundaryPressures()[0];
  EXPECT_TRUE(std::isfinite(pk));
  // Within kMaxSlopeAmplification x the 10 Pa spread of the mean, and at 0 or above.
  EXPECT_LE(std::abs(pk - Real(1000)), BoundaryPressureTreatment::kMaxSlopeAmplification * Real(10) + Real(10));
}
