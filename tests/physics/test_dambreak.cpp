// The bundled dam break at a coarser resolution (r = 0.05) for 1.5 s: no NaN, particle count
// conserved, every particle inside the tank, density error bounded.
#include <gtest/gtest.h>

#include "TestUtil.h"

using namespace consph;

TEST(DamBreak, StaysInsideTheTankWithoutBlowingUp) {
  json scene = readJsonFile(test::dataPath("scenes/DamBreak.json"));
  applyOverride(scene, "simulation.particleRadius", "0.05");
  auto sim = test::simulationFromJson(scene);
  const std::size_t n0 = sim->fluid().size();
  ASSERT_EQ(n0, 10u * 10u * 10u);
  EXPECT_NO_THROW(sim->run(Real(1.5)));
  const FluidModel& f = sim->fluid();
  ASSERT_EQ(f.size(), n0);
  const Vector3r lo(-2, 0, Real(-0.75)), hi(2, 3, Real(0.75));
  for (std::size_t i = 0; i < f.size(); ++i) {
    ASSERT_TRUE(f.positions[i].allFinite() && f.velocities[i].allFinite()) << i;
    ASSERT_TRUE((f.positions[i] - lo).minCoeff() > 0 && (hi - f.positions[i]).minCoeff() > 0)
        << "particle " << i << " at " << f.positions[i].transpose();
  }
  // Ids are a permutation of 0..n-1 after all the re-sorting.
  std::vector<bool> seen(n0, false);
  for (Index id : f.ids) seen.at(id) = true;
  for (bool s : seen) ASSERT_TRUE(s);
  const json summary = sim->summary();
  EXPECT_LT(summary["averageDensityErrorPercent"].get<double>(), 0.1);
  EXPECT_EQ(summary["iterationCapHits"].get<std::size_t>(), 0u);
  // The front reached the far wall (x = 2) region by 1.5 s.
  Real front = -10;
  for (auto& x : f.positions) front = std::max(front, x[0]);
  EXPECT_GT(front, Real(1.5));
}
