// Surface tension: a cube of water without gravity pulls itself towards a sphere, the shape of
// least surface for its volume; without surface tension it stays a cube.
#include <gtest/gtest.h>

#include <numbers>

#include "tests/physics/ForceTestSupport.h"

using namespace consph;
using namespace consph::test;

namespace {

// Radius of gyration of the particles over that of a solid sphere of the same volume
// (N (2r)^3, since blocks start at rest density): 1 for a sphere, 1.035 for a 10^3 cube.
Real gyrationRatio(const FluidModel& f, Real r) {
  Vector3r c = Vector3r::Zero();
  for (auto& x : f.positions) c += x;
  c /= Real(f.size());
  Real rg2 = 0;
  for (auto& x : f.positions) rg2 += (x - c).squaredNorm();
  rg2 /= Real(f.size());
  const Real volume = Real(f.size()) * std::pow(2 * r, Real(3));
  const Real radius = std::cbrt(3 * volume / (4 * std::numbers::pi_v<Real>));
  return std::sqrt(rg2 / (Real(0.6) * radius * radius));
}

std::unique_ptr<Simulation> cube(const std::string& forces) {
  return simulationFromJson(R"({"simulation": {"particleRadius": 0.01, "particleSpacing": 2.0, "gravity": [0, 0, 0]},
      "fluids": [{"forces": [)" + forces + R"(], "blocks": [{"min": [0, 0, 0], "max": [0.2, 0.2, 0.2]}]}]})");
}

TEST(ForcesSurfaceTension, CubeWithoutGravityPullsTowardsASphere) {
  const Real r = 0.01, until = Real(0.3);
  auto tension = cube(R"({"type": "Akinci2013", "surfaceTension": 0.5}, {"type": "StandardViscosity"})");
  const Real start = gyrationRatio(tension->fluid(), r);
  tension->run(until);
  const Real end = gyrationRatio(tension->fluid(), r);
  auto control = cube(R"({"type": "StandardViscosity"})");
  control->run(until);
  const Real controlEnd = gyrationRatio(control->fluid(), r);
  std::printf("R_g / R_g(sphere): cube %.4f, after %.2f s with surface tension %.4f, without %.4f\n", start, until, end, controlEnd);
  EXPECT_LT(end - 1, Real(0.5) * (start - 1));  // at least half-way to the sphere
  EXPECT_GT(controlEnd - 1, Real(0.8) * (start - 1));
}

}  // namespace
