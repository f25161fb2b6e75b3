// Drag: isolated droplets falling through still air reach the terminal speed where drag balances
// gravity, from below (released at rest) and from above (thrown down at twice that speed).
#include <gtest/gtest.h>

#include <numbers>

#include "Plugins/Drag/DragForce_Gissler2017.h"
#include "tests/TestUtil.h"
#include "tests/physics/ForceTestSupport.h"

using namespace consph;
using namespace consph::test;

namespace {

constexpr Real kRadius = Real(0.025), kGravity = Real(9.81);

// Three single-particle blocks 1 m apart (no neighbours: each is a droplet), starting with
// vertical velocities v0[k], falling for `seconds` under gravity with `force`.
std::unique_ptr<Simulation> fallingDroplets(const std::string& force, const std::vector<Real>& v0) {
  std::string blocks;
  for (std::size_t k = 0; k < v0.size(); ++k) {
    const Real x = Real(k);
    blocks += (k ? ", " : "") + std::string("{\"min\": [") + std::to_string(x) + ", 0, 0], \"max\": [" +
              std::to_string(x + 2 * kRadius) + ", 0.05, 0.05], \"velocity\": [0, " + std::to_string(v0[k]) + ", 0]}";
  }
  return simulationFromJson(R"({"simulation": {"particleRadius": 0.025, "particleSpacing": 2.0, "gravity": [0, -9.81, 0]},
      "fluids": [{"forces": [)" + force + R"(], "blocks": [)" + blocks + "]}]}");
}

// Speeds (downwards) after `seconds`, and whether each fell monotonically towards its limit.
std::vector<Real> fallSpeeds(Simulation& sim, Real seconds) {
  sim.run(seconds);
  std::vector<Real> v;
  for (auto& vi : sim.fluid().velocities) v.push_back(-vi[1]);
  return v;
}

// Gissler et al. 2017 above y_max = 1 and Re = 1000: C_D = 0.424 (1 + 2.632) (Eq. 9) and
// A = pi (L + C_b L)^2 (Eq. 12), so m g = c (1/2) rho_a v_t^2 C_D A gives v_t in closed form.
TEST(ForcesDrag, Gissler2017DropletsReachTerminalSpeed) {
  const Real c = 10, pi = std::numbers::pi_v<Real>;
  const Real mass = 1000 * std::pow(2 * kRadius, Real(3));
  const Real L = std::cbrt(Real(3) / (4 * pi)) * 2 * kRadius;
  using G = DragForce_Gissler2017;
  const Real cD = Real(0.424) * (1 + Real(2.632)), area = pi * std::pow(L * (1 + G::cB), Real(2));
  const Real vT = std::sqrt(2 * mass * kGravity / (c * G::airDensity * cD * area));
  auto sim = fallingDroplets(R"({"type": "Gissler2017", "drag": 10})", {0, -2 * vT, -Real(0.5) * vT});
  // The closed form holds only in that regime: check it at v_t.
  ParticleSet probe(1, 1, 1, 2 * kRadius);
  auto model = probe.create("Gissler2017");
  EXPECT_GE(dynamic_cast<G*>(model.get())->deformationCoefficient() * vT * vT, 1);
  EXPECT_GT(2 * G::airDensity * vT * L / G::airViscosity, 1000);

  const auto v = fallSpeeds(*sim, 3);  // 6.7 v_t / g
  std::printf("Gissler2017 terminal speed: analytic %.4f m/s, droplets %.4f %.4f %.4f m/s\n", vT, v[0], v[1], v[2]);
  for (Real vi : v) EXPECT_NEAR(vi, vT, 0.005 * vT);
}

// Macklin et al. 2014 is linear in v: an isolated particle (rho = m W(0)) reaches
// v_t = m g / (c (1 - rho / rho0)) with time constant m / (c (1 - rho / rho0)).
TEST(ForcesDrag, Macklin2014DropletsReachTerminalSpeed) {
  const Real c = 0.5;
  auto sim = fallingDroplets(R"({"type": "Macklin2014", "drag": 0.5})", {0, -8, -2});
  const Real mass = sim->fluid().masses[0];
  const Real missing = 1 - mass * sim->kernel().W0() / sim->fluid().density0();
  const Real vT = mass * kGravity / (c * missing), tau = mass / (c * missing);
  const auto v = fallSpeeds(*sim, 10 * tau);
  std::printf("Macklin2014 terminal speed: analytic %.4f m/s, droplets %.4f %.4f %.4f m/s\n", vT, v[0], v[1], v[2]);
  for (Real vi : v) EXPECT_NEAR(vi, vT, 0.002 * vT);
}

// Without drag the droplets keep accelerating (the control: the limit above is the drag's).
TEST(ForcesDrag, WithoutDragDropletsFallFreely) {
  auto sim = fallingDroplets("", {0});
  const auto v = fallSpeeds(*sim, 1);
  // Float: v and t are each a sum of N = stepCount() increments, each rounded to eps of the
  // running sum (<= g t), so each is off by at most N eps g t.
  const double steps = double(sim->stepCount());
  EXPECT_NEAR(v[0], kGravity * sim->time(), roundoff(1e-9, 2 * steps * kFloatEps * kGravity * sim->time()));
}

}  // namespace
