// Bodies fail loudly like the fluid (Simulation/RigidBodyGuard.h): a body that blows up stops the
// run naming the body, the step and the time (CLI exit 3); a dynamic body with an open mesh is
// refused at load (exit 2); bodies drawn into each other at t = 0 are named in a warning and come
// apart gently (RigidContact::kMaxPushOutSpeed).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "CliUtil.h"
#include "TestUtil.h"

using namespace consph;

namespace {
// A 0.1 m box of `density` held under 0.25 m of water in a 0.4 m tank (r = 0.025).
json submergedBox(double density) {
  json s = json::parse(R"({
    "simulation": {"particleRadius": 0.025, "stopAt": 1.0},
    "fluids": [{"blocks": [{"min": [0.0, 0.0, 0.0], "max": [0.4, 0.25, 0.4]}]}],
    "boundaries": [{"name": "tank", "box": {"min": [0, 0, 0], "max": [0.4, 0.8, 0.4]}, "inverted": true},
                   {"name": "light", "box": {"min": [0.15, 0.08, 0.15], "max": [0.25, 0.18, 0.25]}, "dynamic": true}]})");
  s["boundaries"][1]["density"] = density;
  return s;
}

}  // namespace

// Density 1e-6 (allowed): buoyancy accelerates it at ~1e9 g. Before the guard it reached
// 4e7 m/s and ended 19 000 km away with exit 0; before the added mass (Boundary/AddedMass.h)
// the guard stopped it in its second step. A free body now rises with the fluid it touches.
TEST(RigidBodyGuards, AFeatherLightBodyRisesWithoutBlowingUp) {
  auto sim = test::simulationFromJson(submergedBox(1e-6));
  double fastest = 0;
  while (sim->time() < 0.3) {
    sim->step();
    fastest = std::max(fastest, double(test::rigidBodies(*sim)->bodies()[0].v.norm()));
  }
  std::printf("[ guard ] feather-light box: fastest %.3f m/s, centre at %.3f m after 0.3 s\n", fastest,
              double(test::rigidBodies(*sim)->bodies()[0].x[1]));
  // A frictionless rise with a sphere's added mass (a = 2 g) over the 0.12 m from its centre
  // to the water's surface, and then some: nowhere near the guard's 22 m/s.
  EXPECT_LT(fastest, 2 * std::sqrt(2 * 2 * 9.81 * 0.12));
  EXPECT_GT(test::rigidBodies(*sim)->bodies()[0].x[1], 0.2);  // it rose
}

// A hinged body takes no added mass (advanceHinged): the same feather-light box on an axle
// along its bottom edge is spun up by its buoyancy's torque until the guard stops the run.
json hingedFeather() {
  json s = submergedBox(1e-6);
  s["boundaries"][1]["hinge"] = {{"point", {0.15, 0.08, 0.2}}, {"axis", {0, 0, 1}}};
  return s;
}

TEST(RigidBodyGuards, ABodyThatBlowsUpStopsTheRunNamingItStepAndTime) {
  auto sim = test::simulationFromJson(hingedFeather());
  try {
    sim->run(1.0);
    FAIL() << "no error";
  } catch (const SimulationError& e) {
    const std::string msg = e.what();
    std::printf("[ guard ] %s\n", msg.c_str());
    EXPECT_NE(msg.find("dynamic body 'light' (boundaries[1])"), std::string::npos) << msg;
    EXPECT_NE(msg.find("step "), std::string::npos) << msg;
    EXPECT_NE(msg.find("t = "), std::string::npos) << msg;
    EXPECT_NE(msg.find("beyond the scene's bound"), std::string::npos) << msg;
    EXPECT_LT(sim->time(), 0.1);  // at once, not after a second of flight
  }
}

TEST(RigidBodyGuards, TheCliExitsWith3ForABodyThatBlowsUp) {
  const std::string dir = test::tempDir("consph_body_guard");
  std::ofstream(dir + "/scene.json") << hingedFeather().dump();
  const auto r = test::runCommand(std::string(CONSPH_BINARY) + " " + dir + "/scene.json --quiet --no-output --stop-at 1");
  EXPECT_EQ(r.status, 3) << r.output;
  EXPECT_NE(r.output.find("dynamic body 'light'"), std::string::npos) << r.output;
}

// The bound itself: 10 U, U = sqrt(2 g H) with H = 0.25 m from the water's top (higher than the
// box's) down to the tank's floor: 10 sqrt(2 x 9.81 x 0.25) = 22.1 m/s. A body of the fluid's
// density stays far below it.
TEST(RigidBodyGuards, TheSpeedBoundIsTenTimesTheFreeFallSpeedOfTheScene) {
  test::CapturedLog log;
  auto sim = test::simulationFromJson(submergedBox(1000), log.sink());
  EXPECT_NEAR(sim->speedScale().fallHeight, 0.25, 1e-12);
  EXPECT_NEAR(sim->speedScale().speed, std::sqrt(2 * 9.81 * 0.25), test::fewUlps(1e-9, 2.2));
  sim->run(0.02);  // a body of the fluid's density runs
  bool said = false;
  for (auto& m : log.infos) said |= m.find("dynamic bodies stop the run beyond 22.1") != std::string::npos;
  EXPECT_TRUE(said);
}

TEST(RigidBodyGuards, ANonFiniteBodyStops) {
  auto sim = test::simulationFromJson(submergedBox(500));
  sim->step();
  test::rigidBodies(*sim)->bodies()[0].w = Vector3r(std::nan(""), 0, 0);
  try {
    sim->step();
    FAIL() << "no error";
  } catch (const SimulationError& e) {
    EXPECT_NE(std::string(e.what()).find("dynamic body 'light' (boundaries[1]) has a non-finite"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("step 2"), std::string::npos) << e.what();
  }
}

TEST(RigidBodyGuards, ABodyLeavingTheDomainStops) {
  auto sim = test::simulationFromJson(submergedBox(500));
  sim->step();
  test::rigidBodies(*sim)->bodies()[0].x += Vector3r(0, 5, 0);  // far above the tank, at rest
  try {
    sim->step();
    FAIL() << "no error";
  } catch (const SimulationError& e) {
    EXPECT_NE(std::string(e.what()).find("dynamic body 'light' (boundaries[1]) left the domain"), std::string::npos) << e.what();
  }
}

// A box without its lid still has a positive divergence-theorem volume, a wrong one.
TEST(RigidBodyGuards, AnOpenMeshIsRefusedAsADynamicBody) {
  const std::string dir = test::tempDir("consph_open_mesh");
  std::ofstream obj(dir + "/lidless.obj");
  obj << "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
         "f 1 4 3\nf 1 3 2\nf 1 2 6\nf 1 6 5\nf 2 3 7\nf 2 7 6\nf 3 4 8\nf 3 8 7\nf 4 1 5\nf 4 5 8\n";  // no top (z = 1)
  obj.close();
  json s = submergedBox(500);
  s["boundaries"][1] = {{"name", "cup"}, {"mesh", dir + "/lidless.obj"}, {"scale", {0.1, 0.1, 0.1}},
                        {"translation", {0.15, 0.05, 0.15}}, {"dynamic", true}, {"density", 500}};
  try {
    test::simulationFromJson(s);
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("boundaries[1].mesh: a dynamic body needs a closed mesh"), std::string::npos) << msg;
    EXPECT_NE(msg.find("4 open edges"), std::string::npos) << msg;
    EXPECT_NE(msg.find("centre of mass"), std::string::npos) << msg;
  }
  std::ofstream(dir + "/scene.json") << s.dump();
  const auto r = test::runCommand(std::string(CONSPH_BINARY) + " " + dir + "/scene.json --quiet --no-output --stop-at 0.01");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("boundaries[1].mesh"), std::string::npos) << r.output;
  // The same mesh as a static object is fine (a cup-shaped wall).
  s["boundaries"][1].erase("dynamic");
  s["boundaries"][1].erase("density");
  EXPECT_NO_THROW(test::simulationFromJson(s));
}

// Two free boxes drawn 5 cm into each other (no gravity, no fluid in reach), and a third one 5 cm
// into the floor: a warning names each pair, and the overlaps come apart at most at the push-out
// cap, without spin. Before the cap they flew apart at 0.2 x overlap / dt.
TEST(RigidBodyGuards, OverlappingBodiesAtTheStartWarnAndSeparateGently) {
  test::CapturedLog log;
  auto sim = test::simulationFromJson(json::parse(R"({
    "simulation": {"particleRadius": 0.025, "maxTimeStep": 0.004, "gravity": [0, 0, 0]},
    "fluids": [{"blocks": [{"min": [1.3, 0.0, 1.3], "max": [1.35, 0.05, 1.35]}]}],
    "boundaries": [{"name": "floor", "box": {"min": [-0.5, -0.1, -0.5], "max": [1.5, 0.0, 1.5]}},
                   {"name": "a", "box": {"min": [0.0, 0.3, 0.0], "max": [0.2, 0.5, 0.2]}, "dynamic": true, "density": 1000},
                   {"name": "b", "box": {"min": [0.15, 0.33, 0.02], "max": [0.35, 0.53, 0.22]}, "dynamic": true, "density": 500},
                   {"name": "c", "box": {"min": [0.8, -0.05, 0.8], "max": [1.0, 0.15, 1.0]}, "dynamic": true, "density": 800}]})"),
                                        log.sink());
  auto warned = [&](const std::string& a, const std::string& b) {
    for (auto& m : log.warnings)
      if (m.find(a) != std::string::npos && m.find(b) != std::string::npos && m.find("overlap") != std::string::npos) return true;
    return false;
  };
  EXPECT_TRUE(warned("'a' (boundaries[1])", "'b' (boundaries[2])"));
  EXPECT_TRUE(warned("'floor' (boundaries[0])", "'c' (boundaries[3])"));
  EXPECT_FALSE(warned("'a'", "'c'"));
  const auto& bodies = test::rigidBodies(*sim)->bodies();
  double speed = 0, spin = 0;
  while (sim->time() < 0.3) {
    sim->step();
    for (const RigidBody& b : bodies) speed = std::max(speed, double(b.v.norm())), spin = std::max(spin, double(b.w.norm()));
  }
  std::printf("[ overlap ] peak body speed %.3f m/s, peak spin %.3f rad/s; b - a %.4f m apart in x, c bottom %.4f m\n", speed, spin,
              double(bodies[1].x[0] - bodies[0].x[0]), double(bodies[2].x[1] - 0.1));
  EXPECT_LT(speed, 0.3);  // the cap, 0.25 m/s, plus what friction and iterations add
  EXPECT_LT(spin, 3.0);
  EXPECT_GT(bodies[1].x[0] - bodies[0].x[0], 0.2 - 0.025);  // apart (centres 0.15 m apart at the start)
  EXPECT_GT(bodies[2].x[1] - 0.1, -0.025);                  // out of the floor
}
