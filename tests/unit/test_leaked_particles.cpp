// The run's "particles lost" record (Simulation/LeakedParticles.h): particles deeper than a
// given depth inside a static object's solid, for boxes, closed meshes and containers.
#include <gtest/gtest.h>

#include "Simulation/LeakedParticles.h"
#include "Simulation/Simulation.h"
#include "Utilities/TriangleMesh.h"
#include "TestUtil.h"

using namespace consph;

namespace {
BoundaryObject object(TriangleMesh mesh, bool inverted, bool isBox, const Vector3r& lo = Vector3r::Zero(),
                      const Vector3r& hi = Vector3r::Zero()) {
  BoundaryObject o;
  o.name = std::string("o");  // (a plain literal trips GCC 12's bogus -Wrestrict, PR 105329)
  o.path = std::string("boundaries[0]");
  o.mesh = std::move(mesh);
  o.inverted = inverted;
  o.isBox = isBox;
  o.boxMin = lo;
  o.boxMax = hi;
  return o;
}
}  // namespace

// A box container [0, 1]^3: in it, at its wall, just beyond it (within the depth) and 0.1 m
// beyond it; only the last counts. The same points against the container as a closed mesh
// (the winding number path) give the same count.
TEST(LeakedParticles, OutsideAContainerDeeperThanTheDepth) {
  const Vector3r lo(0, 0, 0), hi(1, 1, 1);
  const std::vector<Vector3r> x = {Vector3r(0.5, 0.5, 0.5), Vector3r(0.5, 0.0, 0.5), Vector3r(0.5, -0.01, 0.5),
                                   Vector3r(0.5, -0.1, 0.5), Vector3r(1.2, 0.5, 0.5)};
  const Real depth = Real(0.025);
  EXPECT_EQ(countParticlesInsideSolids({object(makeBoxMesh(lo, hi, true), true, true, lo, hi)}, x, depth), 2u);
  EXPECT_EQ(countParticlesInsideSolids({object(makeBoxMesh(lo, hi, true), true, false)}, x, depth), 2u);
}

// A body: a sphere mesh of radius 0.2 at the centre; a point at its centre and one 0.15 m out
// are inside (deeper than 0.025), one on its surface and one outside are not.
TEST(LeakedParticles, InsideABodyDeeperThanTheDepth) {
  const Vector3r c(0.5, 0.5, 0.5);
  const std::vector<Vector3r> x = {c, c + Vector3r(0.15, 0, 0), c + Vector3r(0, 0.2, 0), c + Vector3r(0, 0, 0.3)};
  EXPECT_EQ(countParticlesInsideSolids({object(makeSphereMesh(c, Real(0.2), 48, 24), false, false)}, x, Real(0.025)), 2u);
}

// An open container mesh (a box without its lid) has no outside to tell: nothing is counted;
// a moving object is not where its mesh was: skipped too.
TEST(LeakedParticles, OpenContainersAndMovingObjectsAreSkipped) {
  TriangleMesh open = makeBoxMesh(Vector3r::Zero(), Vector3r::Ones(), true);
  open.triangles.pop_back();
  const std::vector<Vector3r> x = {Vector3r(0.5, -0.5, 0.5)};
  EXPECT_EQ(countParticlesInsideSolids({object(open, true, false)}, x, Real(0.025)), 0u);
  BoundaryObject moving = object(makeBoxMesh(Vector3r::Zero(), Vector3r::Ones(), false), false, true, Vector3r::Zero(), Vector3r::Ones());
  moving.motion = BodyMotion::Dynamic;
  EXPECT_EQ(countParticlesInsideSolids({moving}, {Vector3r(0.5, 0.5, 0.5)}, Real(0.025)), 0u);
}

// The summary's record: a block drawn partly through a tank's floor (its lower layers inside
// the solid from the start) reports them lost; the same block inside the tank reports none.
TEST(LeakedParticles, TheSummaryCountsParticlesInTheWalls) {
  for (const double bottom : {0.0, -0.1}) {
    json s = {{"simulation", {{"particleRadius", 0.025}}},
              {"fluids", {{{"blocks", {{{"min", {0.1, bottom, 0.1}}, {"max", {0.3, 0.2, 0.3}}}}}}}},
              {"boundaries", {{{"box", {{"min", {0, 0, 0}}, {"max", {0.5, 0.5, 0.5}}}}, {"inverted", true}}}},
              {"output", {{"enabled", false}}}};
    test::CapturedLog log;
    auto sim = test::simulationFromJson(s, log.sink());
    std::size_t below = 0;  // particles deeper than r under the floor
    for (const Vector3r& x : sim->fluid().positions) below += x[1] < -0.025;
    EXPECT_EQ(sim->summary()["particlesLost"].get<std::size_t>(), below) << "block from y = " << bottom;
    if (bottom < 0) {
      EXPECT_GT(below, 0u);
    }
  }
}
