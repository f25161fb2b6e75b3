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

// Issue 16's mutation test, exit 0 on invalid input: each scene below ran to the end (exit 0)
// before its check existed. Parsed only, no simulation built.
namespace {
std::string parseErrorOf(const json& scene) {
  try {
    parseScene(scene, CONSPH_TEST_DATA_DIR "/scenes", {});
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}
#define EXPECT_REFUSED(scene, text) EXPECT_NE(parseErrorOf(scene).find(text), std::string::npos) << parseErrorOf(scene)
}  // namespace

TEST(SceneValidation, NullIsAWrongTypeNotTheDefault) {
  // A null written for an object or array key used to stand for the key's default silently.
  const std::vector<std::pair<json::json_pointer, std::string>> cases = {
      {json::json_pointer("/simulation"), "simulation: expected an object, got null"},
      {json::json_pointer("/simulation/pressureSolver"), "simulation.pressureSolver: expected an object or a plugin name, got null"},
      {json::json_pointer("/simulation/boundaryModel"), "simulation.boundaryModel: expected an object or a plugin name, got null"},
      {json::json_pointer("/simulation/domain"), "simulation.domain: expected an object, got null"},
      {json::json_pointer("/fluids/0/forces"), "fluids[0].forces: expected an array of force objects, got null"},
      {json::json_pointer("/fluids/0/emitters"), "fluids[0].emitters: expected an array of emitters, got null"},
      {json::json_pointer("/fluids/0/removeOutside"), "fluids[0].removeOutside: expected an object, got null"},
      {json::json_pointer("/fluids/0/particleFiles"), "fluids[0].particleFiles: expected an array, got null"},
      {json::json_pointer("/fluids/0/meshVolumes"), "fluids[0].meshVolumes: expected an array, got null"},
      {json::json_pointer("/boundaries"), "boundaries: expected an array, got null"},
      {json::json_pointer("/output"), "output: expected an object, got null"},
      {json::json_pointer("/probes"), "probes: expected an array of probe objects, got null"},
      {json::json_pointer("/description"), "description: expected a string, got null"}};
  for (auto& [pointer, message] : cases) {
    json s = minimalScene();
    s[pointer] = nullptr;
    EXPECT_REFUSED(s, message);
  }
  json s = minimalScene();  // a moving body: a container cannot be animated
  s["boundaries"].push_back({{"box", {{"min", {0.2, 0.6, 0.2}}, {"max", {0.3, 0.7, 0.3}}}}, {"animated", nullptr}});
  EXPECT_REFUSED(s, "boundaries[1].animated: expected an object");
}

TEST(SceneValidation, DescriptionIsText) {
  json s = minimalScene();
  s["description"] = json::array({1});
  EXPECT_REFUSED(s, "description: expected a string, got array [1]");
}

TEST(SceneValidation, BoundaryNamesArePrintableCsvFieldsAndUnique) {
  for (const char* name : {"ta,nk", "ta\"nk", "ta\nnk", "ta\tnk", "\xc2\x85"}) {  // the last: U+0085, a C1 control
    json s = minimalScene();
    s["boundaries"][0]["name"] = name;
    EXPECT_REFUSED(s, "boundaries[0].name: must be printable UTF-8 text without a comma or a quote");
  }
  json s = minimalScene();
  s["boundaries"][0]["name"] = "tank";
  s["boundaries"].push_back({{"name", "tank"}, {"box", {{"min", {0.2, 0.6, 0.2}}, {"max", {0.3, 0.7, 0.3}}}}});
  EXPECT_REFUSED(s, "boundaries[1].name: 'tank' already names boundaries[0]");
  s["boundaries"][1]["name"] = "lid";
  EXPECT_EQ(parseErrorOf(s), "(no error)");
}

TEST(SceneValidation, TheSameBoundaryTwiceIsRefused) {
  json s = minimalScene();
  s["boundaries"][0]["name"] = "tank";
  s["boundaries"].push_back(s["boundaries"][0]);
  s["boundaries"][1]["name"] = "tank2";
  EXPECT_REFUSED(s, "boundaries[1]: the same object as boundaries[0] (equal but for the name)");
}

TEST(SceneValidation, OverlappingBlocksAreRefusedTouchingOnesAreNot) {
  json s = minimalScene();
  s["fluids"][0]["blocks"].push_back(s["fluids"][0]["blocks"][0]);
  EXPECT_REFUSED(s, "fluids[0].blocks[1]: overlaps fluids[0].blocks[0]: their particles would lie on top of each other");
  s["fluids"][0]["blocks"][1] = {{"min", {0.45, 0.45, 0.45}}, {"max", {0.55, 0.55, 0.55}}};  // one corner inside
  EXPECT_REFUSED(s, "fluids[0].blocks[1]: overlaps fluids[0].blocks[0]");
  s["fluids"][0]["blocks"][1] = {{"min", {0.5, 0.1, 0.1}}, {"max", {0.55, 0.5, 0.5}}};  // face to face
  EXPECT_EQ(parseErrorOf(s), "(no error)");
}

TEST(SceneValidation, TheSameSourceTwiceIsRefused) {
  json s = minimalScene();
  s["fluids"][0]["emitters"] = {{{"position", {0.3, 0.8, 0.3}}, {"direction", {0, -1, 0}}, {"speed", 1}, {"width", 0.1}, {"height", 0.1}}};
  EXPECT_EQ(parseErrorOf(s), "(no error)");
  s["fluids"][0]["emitters"].push_back(s["fluids"][0]["emitters"][0]);
  EXPECT_REFUSED(s, "fluids[0].emitters[1]: the same as fluids[0].emitters[0]: their particles would lie on top of each other");
  s = minimalScene();
  s["fluids"][0]["meshVolumes"] = {{{"mesh", "../meshes/UnitBox.obj"}, {"scale", {0.2, 0.2, 0.2}}, {"translation", {0.1, 0.6, 0.1}}}};
  s["fluids"][0]["meshVolumes"].push_back(s["fluids"][0]["meshVolumes"][0]);
  EXPECT_REFUSED(s, "fluids[0].meshVolumes[1]: the same as fluids[0].meshVolumes[0]");
}

TEST(SceneValidation, EachForceTypeOnce) {
  // A second instance would share the first's particle fields (Weiler2018's last velocity
  // change, Micropolar's angular velocity), each overwriting the other's state.
  json s = minimalScene();
  s["fluids"][0]["forces"] = {{{"type", "StandardViscosity"}, {"viscosity", 0.01}}, {{"type", "XSPH"}}, {{"type", "standardviscosity"}}};
  EXPECT_REFUSED(s, "fluids[0].forces[2]: a second standardviscosity (fluids[0].forces[0] is one)");
  s["fluids"][0]["forces"].erase(2);
  EXPECT_EQ(parseErrorOf(s), "(no error)");
}

TEST(SceneValidation, OutputDirectoryNamesAFolder) {
  for (const char* directory : {"", "out\x01", "out\x7f"}) {
    json s = minimalScene();
    s["output"] = {{"directory", directory}, {"enabled", false}};  // checked even without frames
    EXPECT_REFUSED(s, "output.directory: must name a folder");
  }
}

TEST(SceneValidation, ProbeNamesArePrintableAndRegionIsForForceProbes) {
  json s = minimalScene();
  s["probes"] = {{{"kind", "level"}, {"name", "gauge\t1"}, {"position", {0.3, 0, 0.3}}}};
  EXPECT_REFUSED(s, "probes[0].name: must be printable UTF-8 text without a comma or a quote");
  // "region" belongs to force probes; elsewhere it is an unknown key, warned about.
  s["probes"][0]["name"] = "gauge";
  s["probes"][0]["region"] = {{"min", {0, 0, 0}}, {"max", {1, 1, 1}}};
  test::CapturedLog log;
  parseScene(s, CONSPH_TEST_DATA_DIR "/scenes", log.sink());
  ASSERT_EQ(log.warnings.size(), 1u);
  EXPECT_NE(log.warnings[0].find("unknown key 'probes[0].region'"), std::string::npos) << log.warnings[0];
}

TEST(SceneValidation, HugeDirectionsAndAxesNormaliseWithoutOverflow) {
  // normalize() squares the components: [1e200, 0, 0] overflowed to the zero vector, and the
  // emitter shot along 0, the hinge turned about 0 and a rotation scaled instead of turning.
  const double huge = test::kDoubleBuild ? 1e300 : 1e30;  // float: 1e300 is inf, 1e30 squared overflows
  json s = minimalScene();
  s["fluids"][0]["emitters"] = {{{"position", {0.3, 0.8, 0.3}}, {"direction", {0, -huge, 0}}, {"speed", 1}, {"width", 0.1}, {"height", 0.1}}};
  s["boundaries"].push_back({{"mesh", "../meshes/UnitBox.obj"}, {"scale", {0.1, 0.1, 0.1}}, {"translation", {0.3, 0.8, 0.3}},
                             {"rotationAxis", {0, huge, huge}}, {"rotationAngle", 0.5}, {"dynamic", true}, {"density", 500},
                             {"hinge", {{"point", {0.3, 0.8, 0.3}}, {"axis", {0, 0, huge}}}}});
  const SceneDescription d = parseScene(s, CONSPH_TEST_DATA_DIR "/scenes", {});
  const double tol = test::roundoff(1e-12, 8 * test::kFloatEps);  // a few roundings of unit-size values
  EXPECT_LT((d.fluids[0].emitters[0].direction - Vector3r(0, -1, 0)).norm(), tol);
  EXPECT_LT((d.boundaries[1].hinge.axis - Vector3r(0, 0, 1)).norm(), tol);
  s["boundaries"][1]["rotationAxis"] = {0, 1, 1};
  const SceneDescription unit = parseScene(s, CONSPH_TEST_DATA_DIR "/scenes", {});
  ASSERT_EQ(unit.boundaries[1].mesh.vertices.size(), d.boundaries[1].mesh.vertices.size());
  for (std::size_t v = 0; v < unit.boundaries[1].mesh.vertices.size(); ++v)
    EXPECT_LT((unit.boundaries[1].mesh.vertices[v] - d.boundaries[1].mesh.vertices[v]).norm(), tol) << v;
}
