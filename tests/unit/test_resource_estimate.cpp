// The up-front resource estimate (issue 16): a lattice count that overflowed int ran silently
// with one layer; requests that cannot fit grew to 6 GB and died of bad_alloc after 25-41 s.
#include <gtest/gtest.h>
#include <unistd.h>

#include "Simulation/ResourceEstimate.h"
#include "TestUtil.h"

using namespace consph;

namespace {
std::string errorOf(const json& scene) { return test::sceneErrorOf(scene); }
}  // namespace

TEST(SceneResourceEstimate, LatticeCountsAreFloatingPoint) {
  const FluidBlock block{Vector3r(0, 0, 0), Vector3r(1e12, 1, 1), Vector3r::Zero(), BlockLattice::CellCentred};
  const auto n = latticeCounts(block, Real(0.1));
  EXPECT_NEAR(n[0], 1e13, test::fewUlps(1e4, 1e13));  // int would have overflowed (UB: the run had 169 particles)
  EXPECT_EQ(n[1], 10);
  EXPECT_THROW(checkedCount(3e9, "x"), InputError);
  EXPECT_EQ(checkedCount(12, "x"), 12);
}

TEST(SceneResourceEstimate, OverflowingBlockIsRefusedWithTheEstimate) {
  json scene = test::tinyTankScene(0.01);
  scene["fluids"][0]["blocks"][0]["max"] = {1e12, 0.5, 0.5};
  const std::string e = errorOf(scene);
  EXPECT_NE(e.find("the scene needs about "), std::string::npos) << e;
  EXPECT_NE(e.find("fluid particles"), std::string::npos) << e;
  EXPECT_NE(e.find("32-bit index"), std::string::npos) << e;
}

TEST(SceneResourceEstimate, TooManyParticlesForTheLimitAreRefusedAndTheLimitCanBeRaised) {
  json scene = test::tinyTankScene(0.01);
  scene["simulation"]["maxParticles"] = 100;  // 64 fluid particles, ~2 800 boundary samples at 250 B: ~600 particles' worth
  const std::string e = errorOf(scene);
  EXPECT_NE(e.find("the scene needs about 64 fluid particles, "), std::string::npos) << e;
  EXPECT_NE(e.find("more than the limit of 100 particles"), std::string::npos) << e;
  EXPECT_NE(e.find("raise it with --max-particles N or simulation.maxParticles"), std::string::npos) << e;
  scene["simulation"]["maxParticles"] = 1e4;
  EXPECT_EQ(errorOf(scene), "(no error)");
}

TEST(SceneResourceEstimate, TinyParticlesInALargeBoxAreRefusedForBothBoundaryModels) {
  // r = 1e-5 in a 1 m box: 1.5e10 boundary samples (or 1e14 volume-map cells).
  json scene = test::tinyTankScene(0.01);
  scene["simulation"]["particleRadius"] = 1e-5;
  scene["fluids"][0]["blocks"][0]["max"] = {0.1001, 0.1001, 0.1001};
  for (const char* model : {"Akinci2012", "VolumeMap"}) {
    scene["simulation"]["boundaryModel"] = model;
    const std::string e = errorOf(scene);
    EXPECT_NE(e.find(std::string("the scene needs about ")), std::string::npos) << model << ": " << e;
    EXPECT_NE(e.find(std::string(model) == "VolumeMap" ? "volume-map cells" : "boundary samples"), std::string::npos) << e;
  }
}

TEST(SceneResourceEstimate, HugeEmitterIsRefused) {
  json scene = test::tinyTankScene(0.01);
  scene["fluids"][0]["emitters"] = {{{"position", {0.3, 0.8, 0.3}}, {"direction", {0, -1, 0}}, {"speed", 1}, {"width", 1e6}, {"height", 1e6}}};
  EXPECT_NE(errorOf(scene).find("the scene needs about "), std::string::npos) << errorOf(scene);
}

TEST(SceneResourceEstimate, DefaultLimitIsHalfTheMachinesMemory) {
  const double pages = double(sysconf(_SC_PHYS_PAGES)) * double(sysconf(_SC_PAGE_SIZE));
  EXPECT_NEAR(defaultMaxParticles() * kBytesPerFluidParticle, 0.5 * pages, kBytesPerFluidParticle);
}
