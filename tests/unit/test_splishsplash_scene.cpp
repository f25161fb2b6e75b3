// SPlisHSPlasH scenes run as they are (issue 18): the scenes in data/splishsplash/scenes (copied
// from SPlisHSPlasH 2.16, MIT) convert, load with the mapped values, warn each key consph cannot
// honour once, and run; `consph convert` writes a scene consph runs.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>

#include "CliUtil.h"
#include "Simulation/SplishSplashScene.h"
#include "TestUtil.h"

using namespace consph;
using consph::test::CapturedLog;

namespace {

std::string scenePath(const std::string& name) { return test::dataPath("splishsplash/scenes/" + name + ".json"); }

struct Loaded {
  SceneDescription scene;
  CapturedLog log;
};

std::unique_ptr<Loaded> load(const std::string& name, std::vector<std::pair<std::string, std::string>> overrides = {}) {
  auto l = std::make_unique<Loaded>();
  overrides.emplace_back("output.enabled", "false");
  l->scene = loadSceneFile(scenePath(name), overrides, l->log.sink());
  return l;
}

// The keys warned as not honoured, with how many warnings name each.
std::map<std::string, int> unhonouredKeys(const CapturedLog& log) {
  std::map<std::string, int> keys;
  const std::string prefix = "SPlisHSPlasH key '";
  for (const std::string& w : log.warnings)
    if (w.rfind(prefix, 0) == 0) ++keys[w.substr(prefix.size(), w.find('\'', prefix.size()) - prefix.size())];
  return keys;
}

json convert(const json& scene, CapturedLog& log) { return convertSplishSplashScene(scene, ".", ".", "test", log.sink()); }

// A minimal SPlisHSPlasH scene: one block, no bodies.
json minimalScene() {
  return json::parse(R"({
    "Configuration": {"particleRadius": 0.05},
    "FluidBlocks": [{"start": [0, 0, 0], "end": [1, 1, 1]}]
  })");
}

}  // namespace

TEST(SplishSplashScene, EveryBundledSceneConvertsAndLoads) {
  for (const char* name : {"DamBreakModel", "DoubleDamBreak", "DoubleDamBreakWithSphere", "DragTest", "Emitter"}) {
    SCOPED_TRACE(name);
    EXPECT_TRUE(isSplishSplashScene(readJsonFile(scenePath(name))));
    const auto l = load(name);
    ASSERT_EQ(l->scene.fluids.size(), 1u);
    EXPECT_EQ(l->scene.particleRadius, Real(0.025));
    EXPECT_EQ(l->scene.pressureSolver["type"], "DFSPH");
    // Only the converter's warnings: the consph scene it writes has no key consph does not know.
    // (and the emitters' missing nozzle boxes, a geometry SPlisHSPlasH adds by itself).
    for (const std::string& w : l->log.warnings)
      EXPECT_TRUE(w.rfind("SPlisHSPlasH key '", 0) == 0 || w.rfind("Emitters: SPlisHSPlasH surrounds each nozzle", 0) == 0) << w;
  }
  EXPECT_FALSE(isSplishSplashScene(readJsonFile(test::dataPath("scenes/DamBreak.json"))));
}

TEST(SplishSplashScene, DamBreakModelMapsItsValues) {
  const auto l = load("DamBreakModel");
  const SceneDescription& s = l->scene;
  const json& solver = s.pressureSolver;
  EXPECT_EQ(solver["minIterations"], 2);
  EXPECT_EQ(solver["maxIterations"], 100);
  EXPECT_EQ(solver["maxError"], 0.05);
  EXPECT_EQ(solver["maxIterationsDivergence"], 100);
  EXPECT_EQ(solver["maxErrorDivergence"], 0.1);
  EXPECT_EQ(solver["enableDivergenceSolver"], true);
  EXPECT_EQ(s.boundaryModel["type"], "VolumeMap");  // boundaryHandlingMethod 2
  EXPECT_EQ(s.gravity, Vector3r(0, Real(-9.81), 0));
  EXPECT_EQ(s.initialTimeStep, Real(0.005));  // timeStepSize
  EXPECT_EQ(s.maxTimeStep, Real(0.005));      // cflMaxTimeStepSize, the cap as given
  EXPECT_TRUE(s.maxTimeStepGiven);
  EXPECT_EQ(s.cflFactor, Real(1));
  EXPECT_NEAR(std::pow(double(s.particleSpacing), 3), 0.8 * 8, test::fewUlps(1e-12, 3 * 6.4));  // volume 0.8 (2r)^3

  const FluidDescription& f = s.fluids[0];
  EXPECT_EQ(f.density0, Real(1000));
  ASSERT_EQ(f.forces.size(), 1u);
  EXPECT_EQ(f.forces[0]["type"], "StandardViscosity");
  EXPECT_EQ(f.forces[0]["viscosity"], 0.01);
  // The block: start/end [-0.5, 0, -0.5]..[0.5, 1, 0.5] translated by [-1.45, 0.05, 0].
  ASSERT_EQ(f.blocks.size(), 1u);
  EXPECT_TRUE(f.blocks[0].min.isApprox(Vector3r(Real(-1.95), Real(0.05), Real(-0.5))));
  EXPECT_TRUE(f.blocks[0].max.isApprox(Vector3r(Real(-0.95), Real(1.05), Real(0.5))));
  EXPECT_EQ(f.blocks[0].lattice, BlockLattice::SplishSplashRegular);  // denseMode 0

  // The tank: UnitBox.obj scaled [4, 3, 1.5], moved up 1.5 m, a container (mapInvert).
  ASSERT_EQ(s.boundaries.size(), 1u);
  const BoundaryObject& tank = s.boundaries[0];
  EXPECT_TRUE(tank.inverted);
  Vector3r lo, hi;
  tank.mesh.boundingBox(lo, hi);
  EXPECT_TRUE(lo.isApprox(Vector3r(-2, 0, Real(-0.75)))) << lo.transpose();
  EXPECT_TRUE(hi.isApprox(Vector3r(2, 3, Real(0.75)))) << hi.transpose();
}

TEST(SplishSplashScene, DamBreakModelStartsWithSplishSplashsParticlesAndRuns) {
  const auto l = load("DamBreakModel", {{"simulation.stopAt", "0.02"}});
  Simulation sim(l->scene, builtinPlugins(), l->log.sink());
  // 19^3 particles as SPlisHSPlasH reports for this scene, 2r apart, each of mass rho0 0.8 (2r)^3.
  ASSERT_EQ(sim.fluid().size(), 6859u);
  const Real r = Real(0.025);
  EXPECT_NEAR(double(sim.fluid().masses[0]), 1000 * 0.8 * std::pow(2 * 0.025, 3), test::fewUlps(1e-9, 0.1));
  Vector3r lo = sim.fluid().positions[0], hi = lo;
  for (const Vector3r& x : sim.fluid().positions) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
  EXPECT_TRUE(lo.isApprox(Vector3r(Real(-1.95) + 2 * r, Real(0.05) + 2 * r, Real(-0.5) + 2 * r), Real(1e-6))) << lo.transpose();
  EXPECT_NEAR(double(hi[0] - lo[0]), 18 * 2 * 0.025, test::fewUlps(1e-9, 1));
  sim.run(Real(0.02));
  EXPECT_GE(sim.stepCount(), 4u);
  EXPECT_EQ(sim.fluid().size(), 6859u);
  Real lowest = sim.fluid().positions[0][1];
  for (const Vector3r& x : sim.fluid().positions) lowest = std::min(lowest, x[1]);
  EXPECT_GT(lowest, Real(0));  // held by the tank's floor
}

TEST(SplishSplashScene, UnhonouredKeysAreWarnedOnceEach) {
  const auto l = load("DamBreakModel");
  const std::map<std::string, int> expected = {{"numberOfStepsPerRenderUpdate", 1}, {"particleAttributes", 1}, {"color", 1},
                                               {"isWall", 1},                       {"mapResolution", 1}};
  EXPECT_EQ(unhonouredKeys(l->log), expected);

  // Two bodies with a colour: one warning naming both.
  const auto w = load("DoubleDamBreakWithSphere");
  const auto keys = unhonouredKeys(w->log);
  EXPECT_EQ(keys.at("color"), 1);
  EXPECT_EQ(keys.at("Simulation"), 1);  // PositionBasedDynamics' block
  EXPECT_EQ(keys.at("particleFile"), 1);
  EXPECT_EQ(keys.at("restitution"), 1);
  for (const auto& [key, count] : keys) EXPECT_EQ(count, 1) << key;
  bool bothPaths = false;
  for (const std::string& text : w->log.warnings)
    bothPaths |= text.find("'color'") != std::string::npos && text.find("RigidBodies[0].color, RigidBodies[1].color") != std::string::npos;
  EXPECT_TRUE(bothPaths);
  // The sphere is dynamic with its density and initial velocity.
  const BoundaryObject& sphere = w->scene.boundaries.at(1);
  EXPECT_EQ(sphere.motion, BodyMotion::Dynamic);
  EXPECT_EQ(sphere.density, Real(20));
  EXPECT_EQ(sphere.velocity, Vector3r(1, 0, 0));
  EXPECT_EQ(sphere.friction, Real(0.2));
  EXPECT_EQ(w->scene.maxTimeStep, Real(0.005));
  EXPECT_EQ(w->scene.cflFactor, Real(0.5));
  EXPECT_EQ(w->scene.pressureSolver["maxError"], 0.01);
}

// mapThickness is the same shift of the map's surface in both frameworks: it is carried over;
// mapResolution (a cell count for a cubic-interpolated grid) is warned, with the per-object key
// consph offers instead.
TEST(SplishSplashScene, MapThicknessIsCarriedOverAndMapResolutionNamesMapCellSize) {
  json scene = minimalScene();
  scene["Configuration"]["boundaryHandlingMethod"] = 2;
  scene["RigidBodies"] = json::parse(R"([{"geometryFile": "box.obj", "mapInvert": true, "mapThickness": 0.02,
                                          "mapResolution": [20, 20, 20]}])");
  CapturedLog log;
  const json converted = convert(scene, log);
  EXPECT_EQ(converted["boundaries"][0]["mapThickness"], 0.02);
  const auto keys = unhonouredKeys(log);
  EXPECT_EQ(keys.count("mapThickness"), 0u);
  ASSERT_EQ(keys.count("mapResolution"), 1u);
  bool namesTheKey = false;
  for (const std::string& w : log.warnings) namesTheKey |= w.find("mapCellSize") != std::string::npos;
  EXPECT_TRUE(namesTheKey);
  // 0 (every bundled scene's value) writes no key.
  scene["RigidBodies"][0]["mapThickness"] = 0.0;
  CapturedLog zeroLog;
  EXPECT_FALSE(convert(scene, zeroLog)["boundaries"][0].contains("mapThickness"));
}

TEST(SplishSplashScene, DragAndEmittersMapToTheirPlugins) {
  const auto d = load("DragTest");
  ASSERT_EQ(d->scene.fluids[0].forces.size(), 1u);
  EXPECT_EQ(d->scene.fluids[0].forces[0]["type"], "Gissler2017");  // dragMethod 2
  EXPECT_EQ(d->scene.fluids[0].forces[0]["drag"], 10.0);
  EXPECT_TRUE(d->scene.boundaries.empty());

  const auto e = load("Emitter");
  EXPECT_EQ(std::count_if(e->log.warnings.begin(), e->log.warnings.end(),
                          [](const std::string& w) { return w.find("surrounds each nozzle with a boundary box") != std::string::npos; }),
            1);
  const auto& emitters = e->scene.fluids[0].emitters;
  ASSERT_EQ(emitters.size(), 2u);
  // Box nozzle 8 x 3 particles of 2r, along the unrotated x axis at 2 m/s until t = 2 s.
  EXPECT_FALSE(emitters[0].circle);
  EXPECT_NEAR(double(emitters[0].width), 8 * 0.05, test::fewUlps(1e-12, 0.4));
  EXPECT_NEAR(double(emitters[0].height), 3 * 0.05, test::fewUlps(1e-12, 0.15));
  EXPECT_TRUE(emitters[0].direction.isApprox(Vector3r(1, 0, 0)));
  EXPECT_EQ(emitters[0].speed, Real(2));
  EXPECT_EQ(emitters[0].end, Real(2));
  EXPECT_TRUE(emitters[0].position.isApprox(Vector3r(Real(-1.2), Real(0.75), 0)));
  // Circle 7 particles across, turned half a turn about y: it emits along -x from t = 2 to 5 s.
  EXPECT_TRUE(emitters[1].circle);
  EXPECT_NEAR(double(emitters[1].radius), 7 * 0.025, test::fewUlps(1e-12, 0.175));
  EXPECT_TRUE(emitters[1].direction.isApprox(Vector3r(-1, 0, 0), Real(test::fewUlps(1e-9, 1))));
  EXPECT_EQ(emitters[1].start, Real(2));
  EXPECT_EQ(emitters[1].end, Real(5));
  const auto keys = unhonouredKeys(e->log);
  EXPECT_EQ(keys.count("cflMethod"), 0u);  // 2: iteration-based step control, honoured
  EXPECT_TRUE(e->scene.iterationFeedback);
  EXPECT_FALSE(load("DamBreakModel")->scene.iterationFeedback);  // cflMethod 1
  EXPECT_EQ(keys.count("maxEmitterParticles"), 1u);
  EXPECT_EQ(keys.count("emitterBoxMin"), 0u);  // without emitterReuseParticles the box does nothing in SPlisHSPlasH either
  EXPECT_FALSE(e->scene.fluids[0].removeOutside);
}

TEST(SplishSplashScene, FlatKeysOfOlderScenesAndMethodIds) {
  CapturedLog log;
  json s = minimalScene();
  s["Configuration"]["simulationMethod"] = 3;
  s["Configuration"]["maxError"] = 0.2;
  s["Configuration"]["boundaryHandlingMethod"] = 0;
  s["Materials"] = json::parse(R"([{"id": "Fluid", "density0": 900, "viscosityMethod": 6, "viscosity": 0.5,
                                    "vorticityMethod": 2, "Vorticity confinement": {"vorticity": 0.3}, "vorticity": 7,
                                    "surfaceTensionMethod": 2, "surfaceTension": 0.4, "XSPH": {"xsph": 0.1}}])");
  const json out = convert(s, log);
  const json& sim = out["simulation"];
  EXPECT_EQ(sim["pressureSolver"]["type"], "IISPH");
  EXPECT_EQ(sim["pressureSolver"]["maxError"], 0.2);
  EXPECT_EQ(sim["boundaryModel"]["type"], "Akinci2012");
  const json& f = out["fluids"][0];
  EXPECT_EQ(f["density0"], 900);
  ASSERT_EQ(f["forces"].size(), 4u);
  EXPECT_EQ(f["forces"][0], json({{"type", "Akinci2013"}, {"surfaceTension", 0.4}}));
  EXPECT_EQ(f["forces"][1], json({{"type", "Weiler2018"}, {"viscosity", 0.5}}));
  EXPECT_EQ(f["forces"][2], json({{"type", "VorticityConfinement"}, {"vorticity", 0.3}}));  // the namespaced value wins
  EXPECT_EQ(f["forces"][3], json({{"type", "XSPH"}, {"viscosity", 0.1}}));
  EXPECT_TRUE(log.warnings.empty()) << log.warnings[0];
  // The consph scene it maps to builds.
  EXPECT_EQ(test::sceneErrorOf(out), "(no error)");
}

TEST(SplishSplashScene, UnavailableMethodsAreWarnedAndBadOnesRefused) {
  CapturedLog log;
  json s = minimalScene();
  s["Configuration"]["simulationMethod"] = 2;  // PBF
  s["Configuration"]["PBF"] = {{"maxError", 0.1}};
  s["Configuration"]["WCSPH"] = {{"stiffness", 1000}};
  s["Materials"] = json::parse(R"([{"viscosityMethod": 2, "Bender and Koschier 2017": {"viscosity": 0.1}}, {"id": "Oil"}])");
  const json out = convert(s, log);
  EXPECT_EQ(out["simulation"]["pressureSolver"], json({{"type", "DFSPH"}}));
  EXPECT_TRUE(out["fluids"][0]["forces"].empty());
  const std::map<std::string, int> expected = {{"simulationMethod", 1}, {"PBF", 1},    {"WCSPH", 1},
                                               {"viscosityMethod", 1},  {"Bender and Koschier 2017", 1}, {"Materials", 1}};
  EXPECT_EQ(unhonouredKeys(log), expected);

  auto errorOf = [](json scene) {
    CapturedLog ignored;
    try {
      convert(scene, ignored);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  json bad = minimalScene();
  bad["Configuration"]["simulationMethod"] = 9;
  EXPECT_EQ(errorOf(bad).rfind("Configuration.simulationMethod: unknown method id 9; SPlisHSPlasH's are 0 WCSPH", 0), 0u) << errorOf(bad);
  bad = minimalScene();
  bad["Configuration"]["particleRadius"] = "0.1";
  EXPECT_EQ(errorOf(bad), "Configuration.particleRadius: expected a number");
  bad = minimalScene();
  bad["FluidBlocks"][0]["scale"] = {1, 2};
  EXPECT_EQ(errorOf(bad), "FluidBlocks[0].scale: expected an array of 3 numbers");
  bad = minimalScene();
  bad["Configuration"]["sim2D"] = true;
  EXPECT_EQ(errorOf(bad), "Configuration.sim2D: consph simulates in 3D only");
  bad = minimalScene();
  bad["FluidBlocks"].push_back({{"id", "Oil"}, {"start", {2, 0, 0}}, {"end", {3, 1, 1}}});
  EXPECT_NE(errorOf(bad).find("consph runs one fluid per scene"), std::string::npos) << errorOf(bad);
}

TEST(SplishSplashScene, CliRunsConvertsAndReportsBadInput) {
  const std::string cli = CONSPH_BINARY, dir = test::tempDir("consph_splishsplash_cli");
  // As it is, with `run`: the warnings listed, exit 0.
  auto r = test::runCommand("timeout 120 " + cli + " run " + scenePath("DragTest") + " --stop-at 0.01 --no-output --quiet");
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("warning: SPlisHSPlasH key 'numberOfStepsPerRenderUpdate' not honoured"), std::string::npos) << r.output;

  // Converted into another folder: the mesh path follows, and consph runs the result.
  std::filesystem::create_directories(dir + "/out");
  r = test::runCommand(cli + " convert " + scenePath("DoubleDamBreak") + " " + dir + "/out/scene.json");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("warnings above"), std::string::npos) << r.output;
  const json converted = readJsonFile(dir + "/out/scene.json");
  const std::string mesh = converted["boundaries"][0]["mesh"];
  EXPECT_TRUE(std::filesystem::exists(dir + "/out/" + mesh)) << mesh;
  EXPECT_EQ(converted["fluids"][0]["blocks"].size(), 2u);
  r = test::runCommand("timeout 120 " + cli + " " + dir + "/out/scene.json --stop-at 0.005 --no-output --quiet");
  EXPECT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(r.output.find("warning"), std::string::npos) << r.output;  // a consph scene now: nothing left to warn

  // Bad input: one line naming the file and the JSON path, exit 2.
  json bad = readJsonFile(scenePath("DragTest"));
  bad["Configuration"]["simulationMethod"] = 12;
  std::ofstream(dir + "/bad.json") << bad.dump();
  r = test::runCommand(cli + " " + dir + "/bad.json --no-output --quiet");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("consph: error: " + dir + "/bad.json: Configuration.simulationMethod: unknown method id 12"), std::string::npos)
      << r.output;
  r = test::runCommand(cli + " convert " + test::dataPath("scenes/DamBreak.json") + " " + dir + "/x.json");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("not a SPlisHSPlasH scene"), std::string::npos) << r.output;
}
