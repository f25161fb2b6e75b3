// Scene files: malformed JSON, wrong types, ranges, unknown plugins and keys, missing meshes,
// and --set overrides.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "Simulation/Scene.h"
#include "TestUtil.h"

using namespace consph;

namespace {
json minimalScene() {
  return json::parse(R"({
    "simulation": {"particleRadius": 0.05, "stopAt": 0.01},
    "fluids": [{"name": "water", "blocks": [{"min": [0.1, 0.1, 0.1], "max": [0.5, 0.5, 0.5]}]}],
    "boundaries": [{"box": {"min": [0, 0, 0], "max": [0.6, 1.0, 0.6]}, "inverted": true}]
  })");
}

std::string errorOf(const json& scene) { return test::sceneErrorOf(scene); }

std::string writeTemp(const std::string& name, const std::string& text) {
  const auto path = std::filesystem::temp_directory_path() / name;
  std::ofstream(path) << text;
  return path.string();
}
}  // namespace

TEST(Scene, MinimalSceneBuilds) {
  auto sim = test::simulationFromJson(minimalScene());
  EXPECT_EQ(sim->fluid().size(), 4u * 4u * 4u);
  EXPECT_GT(sim->boundary().size(), 0u);
  const double spacing = sim->scene().particleSpacing * 0.05;  // default 0.8^(1/3) 2r
  EXPECT_NEAR(spacing * spacing * spacing, 0.8 * 0.1 * 0.1 * 0.1, 1e-7);
  // Float: the mass rho0 d^3 is 3 products of floats, and d itself a rounded float (measured 0.5 eps).
  EXPECT_NEAR(sim->fluid().masses[0], 1000 * spacing * spacing * spacing, test::roundoff(1e-9, 4 * test::kFloatEps * 1000 * spacing * spacing * spacing));
}

TEST(Scene, MalformedJsonReportsLineAndColumn) {
  const std::string path = writeTemp("consph_malformed.json", "{\n  \"simulation\": {\n    \"particleRadius\": 0.05,,\n  }\n}\n");
  try {
    readJsonFile(path);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path + ":3:28"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("malformed JSON"), std::string::npos) << e.what();
  }
}

TEST(Scene, MissingFileIsAnError) { EXPECT_THROW(readJsonFile("/nonexistent/scene.json"), InputError); }

TEST(Scene, WrongTypeNamesPath) {
  json s = minimalScene();
  s["simulation"]["particleRadius"] = "big";
  EXPECT_NE(errorOf(s).find("simulation.particleRadius: expected a number"), std::string::npos) << errorOf(s);
  s = minimalScene();
  s["fluids"][0]["blocks"][0]["min"] = {1, 2};
  EXPECT_NE(errorOf(s).find("fluids[0].blocks[0].min: expected an array of 3 numbers"), std::string::npos) << errorOf(s);
}

TEST(Scene, OutOfRangeNamesPath) {
  json s = minimalScene();
  s["fluids"][0]["density0"] = -5;
  EXPECT_NE(errorOf(s).find("fluids[0].density0: value -5 is out of range"), std::string::npos) << errorOf(s);
  s = minimalScene();
  s["simulation"]["pressureSolver"] = {{"type", "DFSPH"}, {"maxError", 0}};
  EXPECT_NE(errorOf(s).find("simulation.pressureSolver.maxError"), std::string::npos) << errorOf(s);
}

TEST(Scene, UnknownPluginListsRegisteredOnes) {
  json s = minimalScene();
  s["fluids"][0]["forces"] = {{{"type", "Visc"}}};
  const std::string msg = errorOf(s);
  EXPECT_NE(msg.find("fluids[0].forces[0].type: unknown non-pressure force 'Visc'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("StandardViscosity"), std::string::npos) << msg;
  s = minimalScene();
  s["simulation"]["boundaryPressure"] = "magic";
  EXPECT_NE(errorOf(s).find("simulation.boundaryPressure: 'magic' is not one of auto consistent mirroring extrapolation"),
            std::string::npos)
      << errorOf(s);
}

TEST(Scene, UnknownKeysWarn) {
  json s = minimalScene();
  s["simulation"]["particleRadios"] = 0.1;
  s["outptu"] = {};
  test::CapturedLog log;
  test::simulationFromJson(s, log.sink());
  ASSERT_EQ(log.warnings.size(), 2u);
  const std::string all = log.warnings[0] + "\n" + log.warnings[1];
  EXPECT_NE(all.find("unknown key 'simulation.particleRadios'"), std::string::npos) << all;
  EXPECT_NE(all.find("known: particleRadius"), std::string::npos) << all;
  EXPECT_NE(all.find("unknown key 'outptu'"), std::string::npos) << all;
}

TEST(Scene, UnknownKeyWarningsListEveryKnownKey) {
  // Issue 16: the lists left out the keys read outside the Params object (top level: "none").
  json s = minimalScene();
  s["nmae"] = 1;
  s["fluids"][0]["blcoks"] = 1;
  s["boundaries"][0]["dinamic"] = 1;
  test::CapturedLog log;
  test::simulationFromJson(s, log.sink());
  ASSERT_EQ(log.warnings.size(), 3u);
  auto warningFor = [&](const std::string& key) {
    for (auto& w : log.warnings)
      if (w.find("unknown key '" + key + "'") != std::string::npos) return w;
    return std::string("(none)");
  };
  EXPECT_NE(warningFor("nmae").find("(known: name, description, simulation, fluids, boundaries, probes, output)"), std::string::npos)
      << warningFor("nmae");
  EXPECT_NE(warningFor("fluids[0].blcoks").find("(known: name, density0, forces, blocks, emitters, removeOutside, particleFiles, meshVolumes)"), std::string::npos)
      << warningFor("fluids[0].blcoks");
  const std::string b = warningFor("boundaries[0].dinamic");
  for (const char* key : {"mesh", "box", "density", "animated", "hinge", "dynamic"}) EXPECT_NE(b.find(key), std::string::npos) << b;
}

TEST(Scene, MissingMeshFileIsAnErrorNamingTheFile) {
  json s = minimalScene();
  s["boundaries"] = {{{"mesh", "no_such_mesh.obj"}}};
  const std::string msg = errorOf(s);
  EXPECT_NE(msg.find("no_such_mesh.obj"), std::string::npos) << msg;
  EXPECT_NE(msg.find("does not exist"), std::string::npos) << msg;
}

TEST(Scene, MeshBoundaryLoadsAndIsTransformed) {
  // With the sample layer on the mesh (surfaceOffset 0) the samples span the transformed box;
  // with the computed offset on every object, the layer sits outside this container, equally
  // on every side.
  for (double offset : {0.0, -1.0}) {
    json s = minimalScene();
    s["simulation"]["boundaryModel"] = {{"type", "Akinci2012"}, {"surfaceOffset", offset}, {"offsetObjects", "all"}};
    s["boundaries"] = {{{"mesh", CONSPH_TEST_DATA_DIR "/meshes/UnitBox.obj"}, {"scale", {0.6, 1.0, 0.6}},
                        {"translation", {0.3, 0.5, 0.3}}, {"inverted", true}}};
    auto sim = test::simulationFromJson(s);
    Vector3r lo = Vector3r::Constant(1e9), hi = -lo;
    for (auto& x : sim->boundary().positions) {
      lo = lo.cwiseMin(x);
      hi = hi.cwiseMax(x);
    }
    const Real grown = -lo[0];
    if (offset == 0) EXPECT_LT(std::abs(grown), 1e-6);
    else EXPECT_TRUE(grown > 0.5 * 0.05 && grown < 2 * 0.05) << grown;
    EXPECT_LT((lo - Vector3r::Constant(-grown)).norm(), 1e-6);
    EXPECT_LT((hi - Vector3r(Real(0.6), 1, Real(0.6)) - Vector3r::Constant(grown)).norm(), 1e-6);
  }
}

TEST(Scene, OverridesSetAnyValueByDottedPath) {
  json s = minimalScene();
  applyOverride(s, "simulation.pressureSolver.maxError", "0.01");
  applyOverride(s, "fluids.0.density0", "998");
  applyOverride(s, "simulation.pressureSolver.type", "WCSPH");  // a bare word is a string
  EXPECT_EQ(s["simulation"]["pressureSolver"]["maxError"].get<double>(), 0.01);
  EXPECT_EQ(s["fluids"][0]["density0"].get<double>(), 998);
  EXPECT_EQ(s["simulation"]["pressureSolver"]["type"].get<std::string>(), "WCSPH");
  EXPECT_THROW(applyOverride(s, "fluids.x.density0", "1"), InputError);
  EXPECT_THROW(applyOverride(s, "fluids.7.density0", "1"), InputError);
  EXPECT_THROW(applyOverride(s, "simulation.particleRadius.x", "1"), InputError);
}
