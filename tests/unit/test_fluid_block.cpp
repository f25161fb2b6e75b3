// Fluid block lattices: consph's cell-centred one and SPlisHSPlasH's denseMode 0, 1 and 2, whose
// counts follow SPlisHSPlasH's rule (round(extent / step) - 1 per axis, from 2r inside the block).
#include <gtest/gtest.h>

#include <cmath>

#include "Simulation/FluidBlock.h"
#include "Utilities/Error.h"

using namespace consph;

namespace {

// The smallest distance between two of `x` (all pairs: the blocks here are small).
double nearestDistance(const std::vector<Vector3r>& x) {
  double best = 1e30;
  for (std::size_t i = 0; i < x.size(); ++i)
    for (std::size_t j = i + 1; j < x.size(); ++j) best = std::min(best, double((x[i] - x[j]).norm()));
  return best;
}

}  // namespace

TEST(FluidBlock, SplishSplashLatticesHaveItsCountsAndSpacing) {
  const Real r = Real(0.05);
  const Real unusedSpacing = 0;  // SPlisHSPlasH's lattices depend on r only
  struct Case {
    BlockLattice lattice;
    std::array<double, 3> counts;  // by SPlisHSPlasH's formulas for a 0.5 m cube at r = 0.05
    double nearest;                // closest pair, in units of 2r
  };
  // denseMode 0: round(0.5 / 0.1) - 1 = 4 per axis. 1: x, z lose 2r first: round(0.4 / 0.1) - 1 = 3,
  // y steps sqrt(3) r: round(0.5 / 0.0866) - 1 = 5. 2: x steps 2 sqrt(6)/3 r and loses one step:
  // round((0.5 - 0.0816) / 0.0816) - 1 = 4.
  // Nearest pairs: 2r on the cubic and the body-centred lattices; the dense one steps columns
  // 2 sqrt(6)/3 (2r) apart with a z offset of r, so its closest pairs are sqrt(2/3 + 1/4) (2r) apart.
  const double dense = std::sqrt(2.0 / 3 + 0.25);
  for (const Case& c : {Case{BlockLattice::SplishSplashRegular, {4, 4, 4}, 1}, Case{BlockLattice::SplishSplashMoreDense, {3, 5, 3}, 1},
                        Case{BlockLattice::SplishSplashDense, {4, 5, 3}, dense}}) {
    SCOPED_TRACE(blockLatticeNames()[std::size_t(c.lattice)]);
    const FluidBlock block{Vector3r(1, 0, 0), Vector3r(Real(1.5), Real(0.5), Real(0.5)), Vector3r::Zero(), c.lattice};
    EXPECT_EQ(blockCounts(block, unusedSpacing, r), c.counts);
    std::vector<Vector3r> x;
    sampleBlock(block, unusedSpacing, r, x);
    ASSERT_EQ(x.size(), std::size_t(c.counts[0] * c.counts[1] * c.counts[2]));
    EXPECT_NEAR(nearestDistance(x), c.nearest * 2 * double(r), 1e-6);
    // Inside the block, at least r from its faces.
    for (const Vector3r& p : x) {
      EXPECT_GE((p - block.min).minCoeff(), r - Real(1e-9));
      EXPECT_GE((block.max - p).minCoeff(), r - Real(1e-9));
    }
  }
  // denseMode 0 starts 2r in from the lower corner, on a 2r grid.
  std::vector<Vector3r> x;
  sampleBlock({Vector3r(1, 0, 0), Vector3r(Real(1.5), Real(0.5), Real(0.5)), Vector3r::Zero(), BlockLattice::SplishSplashRegular},
              unusedSpacing, r, x);
  EXPECT_TRUE(x.front().isApprox(Vector3r(Real(1.1), Real(0.1), Real(0.1))));
  EXPECT_TRUE(x.back().isApprox(Vector3r(Real(1.4), Real(0.4), Real(0.4))));
}

TEST(FluidBlock, ThinSplishSplashBlocksAreEmptyAndCellCentredOnesAreNot) {
  const Real r = Real(0.05);
  // One particle across y by SPlisHSPlasH's rule (round(0.2 / 0.1) - 1): SPlisHSPlasH skips it.
  const FluidBlock thin{Vector3r::Zero(), Vector3r(1, Real(0.2), 1), Vector3r::Zero(), BlockLattice::SplishSplashRegular};
  EXPECT_EQ(blockCounts(thin, 0, r), (std::array<double, 3>{0, 0, 0}));
  std::vector<Vector3r> x;
  sampleBlock(thin, 0, r, x);
  EXPECT_TRUE(x.empty());
  FluidBlock cellCentred = thin;
  cellCentred.lattice = BlockLattice::CellCentred;
  EXPECT_EQ(blockCounts(cellCentred, Real(0.1), r), (std::array<double, 3>{10, 2, 10}));
  sampleBlock(cellCentred, Real(0.1), r, x);
  ASSERT_EQ(x.size(), 200u);
  EXPECT_TRUE(x.front().isApprox(Vector3r(Real(0.05), Real(0.05), Real(0.05))));
  EXPECT_EQ(blockLatticeFromName("splishsplashDense"), BlockLattice::SplishSplashDense);
  EXPECT_THROW(blockLatticeFromName("hexagonal"), InputError);
}
