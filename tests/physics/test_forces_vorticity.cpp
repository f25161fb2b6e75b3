// Vorticity: a Lamb-Oseen vortex in a slab of water (no gravity, free surfaces, DFSPH) loses
// kinetic energy to viscosity; vorticity confinement and the micropolar model put energy back.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <numbers>

#include "tests/physics/ForceTestSupport.h"

using namespace consph;
using namespace consph::test;

namespace {

constexpr Real kCoreRadius = Real(0.15);  // r_c, m
constexpr Real kCirculation = Real(0.75);  // Gamma, m^2/s: peak speed 0.48 m/s at 1.12 r_c

// Lamb-Oseen vortex about the z axis: v_theta = Gamma / (2 pi s) (1 - exp(-s^2 / r_c^2)),
// vorticity omega_z = Gamma / (pi r_c^2) exp(-s^2 / r_c^2) (s: distance from the axis).
Vector3r vortexVelocity(const Vector3r& x) {
  const Real s2 = x[0] * x[0] + x[1] * x[1];
  if (s2 == 0) return Vector3r::Zero();
  const Real vTheta = kCirculation / (2 * std::numbers::pi_v<Real>) * (1 - std::exp(-s2 / (kCoreRadius * kCoreRadius))) / s2;
  return vTheta * Vector3r(-x[1], x[0], 0);  // v_theta / s * (-y, x)
}
Real vortexVorticity(const Vector3r& x) {
  const Real s2 = x[0] * x[0] + x[1] * x[1];
  return kCirculation / (std::numbers::pi_v<Real> * kCoreRadius * kCoreRadius) * std::exp(-s2 / (kCoreRadius * kCoreRadius));
}

// The vortex in a 0.96 x 0.96 x 0.24 m slab, r = 0.02 m (3456 particles), with standard
// viscosity nu = 0.01 m^2/s plus `extraForces`, started with the vortex velocity field.
std::unique_ptr<Simulation> vortexSimulation(const std::string& extraForces) {
  auto sim = simulationFromJson(R"({"simulation": {"particleRadius": 0.02, "gravity": [0, 0, 0], "sortInterval": 0},
      "fluids": [{"forces": [{"type": "StandardViscosity", "viscosity": 0.01})" + extraForces + R"(],
                  "blocks": [{"min": [-0.48, -0.48, -0.12], "max": [0.48, 0.48, 0.12]}]}]})");
  FluidModel& f = sim->fluid();
  for (std::size_t i = 0; i < f.size(); ++i) f.velocities[i] = vortexVelocity(f.positions[i]);
  return sim;
}

Real runAndMeasureEnergy(Simulation& sim, Real until) {
  sim.run(until);
  return kineticEnergy(sim.fluid());
}

// The energy the force alone feeds in at t = 0, sum_i m_i v_i . a_i (W), on the initial lattice.
Real initialPower(const std::string& type, const json& params, bool equilibriumOmega) {
  ParticleSet set(24, 24, 6, 0.04);
  const Vector3r c = set.centre();
  for (auto& x : set.fluid.positions) x -= c;
  set.update();
  for (std::size_t i = 0; i < set.fluid.size(); ++i) set.fluid.velocities[i] = vortexVelocity(set.fluid.positions[i]);
  auto force = set.create(type, params);
  if (equilibriumOmega) {
    auto& omega = set.fluid.fields().get<Vector3r>("angularVelocity");
    for (std::size_t i = 0; i < set.fluid.size(); ++i) omega[i] = Vector3r(0, 0, vortexVorticity(set.fluid.positions[i]) / 2);
  }
  const auto a = set.accelerations(*force, 0.005);
  Real power = 0;
  for (std::size_t i = 0; i < a.size(); ++i) power += set.fluid.masses[i] * set.fluid.velocities[i].dot(a[i]);
  return power;
}

TEST(ForcesVorticity, ConfinementAddsEnergyToAVortexThatViscosityDamps) {
  EXPECT_GT(initialPower("VorticityConfinement", json::object(), false), 0);
  auto plain = vortexSimulation("");
  const Real e0 = kineticEnergy(plain->fluid());
  const Real ePlain = runAndMeasureEnergy(*plain, 0.2);
  auto confined = vortexSimulation(R"(, {"type": "VorticityConfinement"})");
  const Real eConfined = runAndMeasureEnergy(*confined, 0.2);
  std::printf("kinetic energy after 0.2 s / initial: plain %.4f, with vorticity confinement %.4f\n", ePlain / e0, eConfined / e0);
  EXPECT_LT(ePlain, e0);
  EXPECT_GT(eConfined, ePlain);
}

// Micropolar (SPlisHSPlasH-like coefficients): omega grows along curl v from rest; once it has
// relaxed to curl v / 2, nu_t curl omega = -(nu_t / 2) laplacian v feeds energy in.
TEST(ForcesVorticity, MicropolarAngularVelocityFollowsCurlAndAddsEnergy) {
  const json params = {{"vorticity", 0.15}, {"inertiaInverse", 0.5}, {"viscosityOmega", 0.05}};
  // Power at omega = curl v / 2: P = rho0 nu_t int v . curl omega dV = (nu_t / 2) rho0 int omega_z^2 dV
  // (the surface term int (omega x v) . n dA vanishes: omega is vertical, v horizontal, and omega
  // is e^-10 at the sides), with int omega_z^2 dA = Gamma^2 / (2 pi r_c^2) per metre of depth.
  const Real pi = std::numbers::pi_v<Real>, depth = Real(0.24), nuT = 0.15;
  const Real expected = nuT / 2 * 1000 * kCirculation * kCirculation / (2 * pi * kCoreRadius * kCoreRadius) * depth;
  const Real power = initialPower("Micropolar", params, true);
  std::printf("micropolar power at omega = curl v / 2: %.3f W (analytic %.3f W)\n", power, expected);
  EXPECT_NEAR(power, expected, 0.02 * expected);
  const std::string force = R"(, {"type": "Micropolar", "vorticity": 0.15, "inertiaInverse": 0.5, "viscosityOmega": 0.05})";

  // From omega = 0, one step turns omega towards the vortex's own rotation (+z in the core).
  auto fromRest = vortexSimulation(force);
  fromRest->step();
  const auto& omega = fromRest->fluid().fields().get<Vector3r>("angularVelocity");
  Real alignment = 0;
  for (std::size_t i = 0; i < omega.size(); ++i) alignment += omega[i][2] * vortexVorticity(fromRest->fluid().positions[i]);
  EXPECT_GT(alignment, 0);

  auto plain = vortexSimulation("");
  const Real e0 = kineticEnergy(plain->fluid());
  const Real ePlain = runAndMeasureEnergy(*plain, 0.2);
  auto micropolar = vortexSimulation(force);
  auto& w = micropolar->fluid().fields().get<Vector3r>("angularVelocity");
  for (std::size_t i = 0; i < w.size(); ++i) w[i] = Vector3r(0, 0, vortexVorticity(micropolar->fluid().positions[i]) / 2);
  const Real eMicropolar = runAndMeasureEnergy(*micropolar, 0.2);
  std::printf("kinetic energy after 0.2 s / initial: plain %.4f, micropolar %.4f\n", ePlain / e0, eMicropolar / e0);
  EXPECT_GT(eMicropolar, ePlain);
}

}  // namespace
