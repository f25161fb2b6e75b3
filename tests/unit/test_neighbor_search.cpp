// Neighbour search: equals brute force, before and after Z-order re-sorting.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <set>

#include "Simulation/NeighborSearch.h"
#include "Utilities/Error.h"

using namespace consph;

namespace {
std::vector<Vector3r> randomPoints(std::size_t n, unsigned seed, Real extent) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-extent, extent);
  std::vector<Vector3r> p(n);
  for (auto& x : p) x = Vector3r(Real(u(rng)), Real(u(rng)), Real(u(rng)));
  return p;
}

void expectBruteForce(const std::vector<Vector3r>& targets, const std::vector<Vector3r>& queries, const NeighborLists& lists,
                      const CubicSplineKernel& kernel, bool excludeSelf) {
  const Real h2 = kernel.supportRadius() * kernel.supportRadius();
  // Cached gradients equal a fresh evaluation up to round-off (FMA contraction may differ).
  const Real gradScale = kernel.W0() / kernel.supportRadius();
  const Real tol = (sizeof(Real) == 8 ? Real(1e-12) : Real(1e-5)) * gradScale;
  ASSERT_EQ(lists.queryCount(), queries.size());
  for (std::size_t i = 0; i < queries.size(); ++i) {
    std::vector<Index> expected;
    for (std::size_t j = 0; j < targets.size(); ++j)
      if ((queries[i] - targets[j]).squaredNorm() <= h2 && !(excludeSelf && i == j)) expected.push_back(Index(j));
    std::vector<Index> got(lists.indices.begin() + lists.begin(i), lists.indices.begin() + lists.end(i));
    std::sort(got.begin(), got.end());
    ASSERT_EQ(got, expected) << "query " << i;  // same set, no duplicates
    for (Index e = lists.begin(i); e < lists.end(i); ++e) {
      const Vector3r xij = queries[i] - targets[lists.indices[e]];
      const Vector3r cached = lists.gradW.empty() ? lists.gradient(e, xij) : lists.gradW[e];
      if (lists.gradW.empty() && sizeof(Real) == 8)  // factors: the very bits of a fresh evaluation
        EXPECT_EQ(cached, kernel.gradW(xij));
      else  // vectors; factors in float, whose distances come from the search's squared ones (SIMD)
        EXPECT_LT((cached - kernel.gradW(xij)).norm(), tol);
    }
  }
}
}  // namespace

TEST(NeighborSearch, SelfSearchEqualsBruteForce) {
  const CubicSplineKernel kernel(Real(0.1));
  const auto points = randomPoints(3000, 1, Real(0.5));
  PointGrid grid;
  grid.build(points.data(), points.size(), kernel.supportRadius());
  NeighborLists lists;
  buildNeighborLists(grid, points.data(), points.size(), kernel, true, PairGradients::Vectors, lists);
  expectBruteForce(points, points, lists, kernel, true);
  ASSERT_TRUE(lists.gradFactors.empty());
  // The fluid's own lists keep each gradient as the factor of x_ij (and reuse `lists`: the
  // vectors of the call before must not linger).
  buildNeighborLists(grid, points.data(), points.size(), kernel, true, PairGradients::Factors, lists);
  EXPECT_TRUE(lists.gradW.empty());
  ASSERT_EQ(lists.gradFactors.size(), lists.pairCount());
  expectBruteForce(points, points, lists, kernel, true);
}

TEST(NeighborSearch, CrossSetSearchEqualsBruteForce) {
  const CubicSplineKernel kernel(Real(0.08));
  const auto targets = randomPoints(2000, 2, Real(0.4));
  const auto queries = randomPoints(1500, 3, Real(0.5));
  PointGrid grid;
  grid.build(targets.data(), targets.size(), kernel.supportRadius());
  NeighborLists lists;
  buildNeighborLists(grid, queries.data(), queries.size(), kernel, false, PairGradients::Vectors, lists);
  expectBruteForce(targets, queries, lists, kernel, false);
}

TEST(NeighborSearch, NegativeAndFarCoordinatesDoNotAlias) {
  // Points far apart whose cells hash to the same bucket must not be reported as neighbours.
  const CubicSplineKernel kernel(Real(0.1));
  auto points = randomPoints(500, 4, Real(0.3));
  for (auto p : randomPoints(500, 5, Real(0.3))) points.push_back(p + Vector3r(Real(1000), Real(-2000), Real(512)));
  PointGrid grid;
  grid.build(points.data(), points.size(), kernel.supportRadius());
  NeighborLists lists;
  buildNeighborLists(grid, points.data(), points.size(), kernel, true, PairGradients::Vectors, lists);
  expectBruteForce(points, points, lists, kernel, true);
}

TEST(NeighborSearch, ZOrderIsAPermutationAndSearchStillExact) {
  const CubicSplineKernel kernel(Real(0.1));
  auto points = randomPoints(2500, 6, Real(0.5));
  const auto order = zOrderPermutation(points.data(), points.size(), kernel.supportRadius());
  std::set<Index> unique(order.begin(), order.end());
  ASSERT_EQ(unique.size(), points.size());
  std::vector<Vector3r> sorted(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) sorted[i] = points[order[i]];
  // Sorting improves locality: consecutive points are closer on average.
  auto meanGap = [](const std::vector<Vector3r>& p) {
    double s = 0;
    for (std::size_t i = 1; i < p.size(); ++i) s += (p[i] - p[i - 1]).norm();
    return s / double(p.size() - 1);
  };
  EXPECT_LT(meanGap(sorted), 0.5 * meanGap(points));
  PointGrid grid;
  grid.build(sorted.data(), sorted.size(), kernel.supportRadius());
  NeighborLists lists;
  buildNeighborLists(grid, sorted.data(), sorted.size(), kernel, true, PairGradients::Vectors, lists);
  expectBruteForce(sorted, sorted, lists, kernel, true);
}

// With kernel weights the build also sums w_j W_ij over each list (after w_i W(0) for a self
// search): the fluid part of the density, Eq. (14), that computeDensities reads. The sum must be
// the one a loop over the finished list gives (to round-off: the two may contract to FMA
// differently), and a later build without weights must not leave the old sums behind.
TEST(NeighborSearch, KernelSumsAreTheListsWeightedKernelSums) {
  const CubicSplineKernel kernel(Real(0.1));
  const auto points = randomPoints(3000, 10, Real(0.5));
  std::vector<Real> weights(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) weights[i] = Real(1) + Real(i % 7) / Real(10);
  PointGrid grid;
  grid.build(points.data(), points.size(), kernel.supportRadius());
  for (bool self : {true, false}) {
    NeighborLists lists;
    buildNeighborLists(grid, points.data(), points.size(), kernel, self, PairGradients::Vectors, lists, weights.data());
    ASSERT_EQ(lists.kernelSums.size(), points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
      Real sum = self ? weights[i] * kernel.W0() : Real(0);
      for (Index e = lists.begin(i); e < lists.end(i); ++e) sum += weights[lists.indices[e]] * kernel.W(points[i] - points[lists.indices[e]]);
      ASSERT_NEAR(lists.kernelSums[i], sum, (sizeof(Real) == 8 ? 1e-12 : 1e-5) * sum) << "query " << i << (self ? " (self search)" : "");
    }
    buildNeighborLists(grid, points.data(), points.size(), kernel, self, PairGradients::Vectors, lists);
    EXPECT_TRUE(lists.kernelSums.empty());
  }
}

TEST(NeighborSearch, TransposeReversesEveryPair) {
  const CubicSplineKernel kernel(Real(0.1));
  const auto targets = randomPoints(800, 7, Real(0.3));
  const auto queries = randomPoints(900, 8, Real(0.3));
  PointGrid grid;
  grid.build(targets.data(), targets.size(), kernel.supportRadius());
  NeighborLists lists, reversed;
  buildNeighborLists(grid, queries.data(), queries.size(), kernel, false, PairGradients::Vectors, lists);
  transposeNeighborLists(lists, targets.size(), reversed);
  ASSERT_EQ(reversed.pairCount(), lists.pairCount());
  for (std::size_t k = 0; k < targets.size(); ++k)
    for (Index e = reversed.begin(k); e < reversed.end(k); ++e) {
      const Index i = reversed.indices[e];
      EXPECT_LE((targets[k] - queries[i]).norm(), kernel.supportRadius());
      EXPECT_LT((reversed.gradW[e] - kernel.gradW(targets[k] - queries[i])).norm(),
                (sizeof(Real) == 8 ? 1e-12 : 1e-5) * kernel.W0() / kernel.supportRadius());
    }
}

TEST(NeighborSearch, EmptySets) {
  const CubicSplineKernel kernel(Real(0.1));
  PointGrid grid;
  grid.build(nullptr, 0, kernel.supportRadius());
  const auto queries = randomPoints(10, 9, Real(0.1));
  NeighborLists lists;
  buildNeighborLists(grid, queries.data(), queries.size(), kernel, false, PairGradients::Vectors, lists);
  EXPECT_EQ(lists.pairCount(), 0u);
  EXPECT_EQ(lists.queryCount(), 10u);
}

TEST(NeighborSearch, NonFinitePointsAreRefusedNotLoopedOn) {
  // Issue 16: an inf point made the cell-growing loop run forever; a NaN one escaped min/max.
  const Real inf = std::numeric_limits<Real>::infinity(), nan = std::numeric_limits<Real>::quiet_NaN();
  for (const Vector3r& bad : {Vector3r(inf, 0, 0), Vector3r(0, nan, 0), Vector3r(-1e308, 0, 0)}) {
    std::vector<Vector3r> points = {Vector3r(0, 0, 0), bad, Vector3r(1, 1, 1)};
    if (bad[0] == Real(-1e308)) points.push_back(Vector3r(1e308, 0, 0));  // finite points spanning more than a double
    PointGrid grid;
    EXPECT_THROW(grid.build(points.data(), points.size(), Real(0.1)), SimulationError) << bad.transpose();
  }
}

// A pair lists both ways or not at all, also at the support radius itself, where the rounding of
// |x_i - x_j|^2 decides: every candidate of a build, whichever SIMD block or tail of its cell
// range it falls in, takes one formula. Points on spheres of radius h about a few centres (their
// distances h to within an ulp or two) and a scatter of others that puts the sphere points at
// varying places in their ranges.
TEST(NeighborSearch, ListsAreSymmetricAtTheSupportRadius) {
  const CubicSplineKernel kernel(Real(0.1));
  const Real h = kernel.supportRadius();
  std::mt19937 rng(7);
  std::normal_distribution<double> normal;
  auto points = randomPoints(600, 2, Real(0.4));
  for (int c = 0; c < 6; ++c) {
    const Vector3r centre = points[std::size_t(c) * 50];
    for (int s = 0; s < 300; ++s) {
      Vector3r d(Real(normal(rng)), Real(normal(rng)), Real(normal(rng)));
      points.push_back(centre + h * d.normalized());
    }
  }
  PointGrid grid;
  grid.build(points.data(), points.size(), h);
  NeighborLists lists;
  buildNeighborLists(grid, points.data(), points.size(), kernel, true, PairGradients::Factors, lists);
  std::set<std::pair<Index, Index>> pairs;
  for (std::size_t i = 0; i < points.size(); ++i)
    for (Index e = lists.begin(i); e < lists.end(i); ++e) pairs.insert({Index(i), lists.indices[e]});
  std::size_t atRadius = 0;
  for (const auto& [i, j] : pairs) {
    EXPECT_TRUE(pairs.count({j, i})) << "j = " << j << " lists i = " << i << " but not the other way round";
    atRadius += std::abs((points[i] - points[j]).norm() - h) < Real(1e-5) * h;
  }
  EXPECT_GT(atRadius, 1000u);  // the test exercised the radius itself
}
