// Hostile input through the CLI (issue 16): each must end with one line naming the option, file
// or JSON path and exit code 2; never a crash, a hang or a silent default.
#include <gtest/gtest.h>

#include <fstream>

#include "CliUtil.h"
#include "TestUtil.h"

using namespace consph;
using consph::test::runCommand;
using consph::test::tempDir;

namespace {
json tinyScene() { return test::tinyTankScene(0.01); }

// Runs the CLI on `sceneText` (written to DIR/scene.json) with `args`, under a timeout: a hang
// shows as exit 124.
test::CommandResult runScene(const std::string& dir, const std::string& sceneText, const std::string& args) {
  std::ofstream(dir + "/scene.json") << sceneText;
  return runCommand("timeout 60 " + std::string(CONSPH_BINARY) + " " + dir + "/scene.json --quiet --no-output " + args);
}

std::size_t lines(const std::string& s) { return std::size_t(std::count(s.begin(), s.end(), '\n')); }

// Expects exit 2 with exactly one line that contains `text`.
void expectRefused(const test::CommandResult& r, const std::string& text) {
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_EQ(lines(r.output), 1u) << r.output;
  EXPECT_NE(r.output.find(text), std::string::npos) << r.output;
}

const char* kCube =
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
    "f 1 4 3\nf 1 3 2\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\nf 4 8 7\nf 4 7 3\nf 1 5 8\nf 1 8 4\nf 2 3 7\nf 2 7 6\n";
}  // namespace

TEST(InputFailures, NonFiniteTimesAndRatesAreRefused) {
  const std::string dir = tempDir("consph_input_times");
  const std::string scene = tinyScene().dump();
  expectRefused(runScene(dir, scene, "--stop-at nan"), "--stop-at: expected a finite number, got 'nan'");
  expectRefused(runScene(dir, scene, "--stop-at inf"), "--stop-at: expected a finite number, got 'inf'");
  expectRefused(runScene(dir, scene, "--stop-at 1e10"), "--stop-at: must be in [0, 1e9] s");
  expectRefused(runScene(dir, scene, "--fps nan"), "--fps: expected a finite number, got 'nan'");
  expectRefused(runScene(dir, scene, "--threads inf"), "--threads: expected a finite number");
}

TEST(InputFailures, HugeThreadCountIsClampedWithAWarning) {
  const std::string dir = tempDir("consph_input_threads");
  const std::string summary = dir + "/summary.json";
  const auto r = runScene(dir, tinyScene().dump(), "--threads 100000 --summary-json " + summary);
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("--threads: 100000 threads clamped to"), std::string::npos) << r.output;
  EXPECT_LE(readJsonFile(summary)["threads"].get<int>(), 1024);
}

TEST(InputFailures, OverflowingNumberNamesFileLineAndColumn) {
  const std::string dir = tempDir("consph_input_overflow");
  std::string scene = tinyScene().dump();
  scene.replace(scene.find("0.01"), 4, "1e999");
  const auto r = runScene(dir, scene, "");
  expectRefused(r, dir + "/scene.json:1:");
  EXPECT_NE(r.output.find("number 1e999 is out of the range of a double"), std::string::npos) << r.output;
  expectRefused(runScene(dir, tinyScene().dump(), "--set simulation.stopAt=1e999"), "--set simulation.stopAt:1:1: number 1e999");
}

TEST(InputFailures, NonStringNameNamesThePath) {
  const std::string dir = tempDir("consph_input_name");
  json scene = tinyScene();
  scene["name"] = 5;
  expectRefused(runScene(dir, scene.dump(), ""), "error: " + dir + "/scene.json: name: expected a string, got number 5");
  scene = tinyScene();
  scene["fluids"][0]["name"] = json::array();
  expectRefused(runScene(dir, scene.dump(), ""), "error: " + dir + "/scene.json: fluids[0].name: expected a string");
}

TEST(InputFailures, DeepJsonIsAnErrorNotACrash) {
  const std::string dir = tempDir("consph_input_deep");
  std::string scene = tinyScene().dump();
  scene.insert(1, "\"description\": " + std::string(100000, '[') + std::string(100000, ']') + ", ");
  const auto r = runScene(dir, scene, "");
  expectRefused(r, dir + "/scene.json:1:");
  EXPECT_NE(r.output.find("JSON nested deeper than 200 levels"), std::string::npos) << r.output;
}

TEST(InputFailures, NonFiniteMeshVertexIsRefusedForBothBoundaryModels) {
  const std::string dir = tempDir("consph_input_mesh");
  for (const char* bad : {"inf", "nan", "1e999"}) {
    std::string obj = kCube;
    obj.replace(obj.find("v 1 1 1"), 7, std::string("v 1 ") + bad + " 1");
    std::ofstream(dir + "/bad.obj") << obj;
    json scene = tinyScene();
    scene["boundaries"].push_back({{"mesh", "bad.obj"}, {"translation", {2, 2, 2}}});
    for (const char* model : {"Akinci2012", "VolumeMap"}) {
      scene["simulation"]["boundaryModel"] = model;
      expectRefused(runScene(dir, scene.dump(), ""), "mesh file '" + dir + "/bad.obj': vertex 7 is not finite");
    }
  }
}

TEST(InputFailures, DegenerateOrOverflowingTransformsAreRefused) {
  const std::string dir = tempDir("consph_input_transform");
  std::ofstream(dir + "/cube.obj") << kCube;
  json scene = tinyScene();
  scene["boundaries"].push_back({{"mesh", "cube.obj"}, {"scale", {-1e308, 0, 0}}});
  expectRefused(runScene(dir, scene.dump(), ""), "boundaries[1].scale: must not be 0 on any axis");
  // Finite coordinates, but a surface of ~1e308 m^2: refused by the size estimate, up front.
  scene["boundaries"][1]["scale"] = {-1e308, 1, 1};
  // (A float build cannot hold 1e308 at all: its transformed coordinates are refused first.)
  expectRefused(runScene(dir, scene.dump(), ""), test::kDoubleBuild ? "boundary samples (~inf GB): more than a 32-bit index holds"
                                                                    : "the transformed object (scale, rotation, translation) has coordinates beyond");
  scene["boundaries"][1]["scale"] = {1e308, 1e308, 1e308};
  scene["boundaries"][1]["translation"] = {1e308, 0, 0};  // 1e308 + 1e308 = inf
  expectRefused(runScene(dir, scene.dump(), ""), "boundaries[1]: the transformed object (scale, rotation, translation) has coordinates beyond");
  scene["boundaries"][1] = {{"box", {{"min", {0, 0, 0}}, {"max", {1, 1, 1}}}}, {"rotationAngle", 1}, {"rotationAxis", {0, 0, 0}}};
  expectRefused(runScene(dir, scene.dump(), ""), "boundaries[1].rotationAxis: must not be the zero vector");
  scene = tinyScene();
  scene["simulation"]["domain"] = {{"min", {0, 0, 0}}, {"max", {0, 1, 1}}};
  expectRefused(runScene(dir, scene.dump(), ""), "simulation.domain: max must exceed min");
}

// What starts outside the escape domain stopped the first step as "leaked through a boundary or
// the simulation blew up" (exit 3; 17 of 2000 mutants): the fluid, an emitter or a dynamic body
// outside it at t = 0 is now an input error naming the cause and the domain.
TEST(InputFailures, FluidEmittersAndBodiesStartingOutsideTheDomainAreRefused) {
  json below = test::tinyTankScene(0.01);
  below["fluids"][0]["blocks"][0]["min"][1] = -1;  // a block through the tank's floor, far below it
  EXPECT_NE(test::sceneErrorOf(below).find("fluids[0]: "), std::string::npos);
  EXPECT_NE(test::sceneErrorOf(below).find("particles start outside the domain (-0.23, -0.25, -0.23) - (0.83, 1.25, 0.83) (the static boundaries' box"),
            std::string::npos)
      << test::sceneErrorOf(below);
  json narrow = test::tinyTankScene(0.01);
  narrow["simulation"]["domain"] = {{"min", {0, 0, 0}}, {"max", {0.3, 1, 0.6}}};
  EXPECT_NE(test::sceneErrorOf(narrow).find("start outside the domain (0, 0, 0) - (0.3, 1, 0.6), the first at"), std::string::npos)
      << test::sceneErrorOf(narrow);
  json emitter = test::tinyTankScene(0.01);
  emitter["fluids"][0]["emitters"] =
      json::parse(R"([{"position": [0.3, 3, 0.3], "direction": [0, -1, 0], "width": 0.1, "height": 0.1, "speed": 1}])");
  EXPECT_NE(test::sceneErrorOf(emitter).find("fluids[0].emitters[0].position: (0.3, 3, 0.3) is outside the domain"), std::string::npos)
      << test::sceneErrorOf(emitter);
  json body = test::tinyTankScene(0.01);
  body["boundaries"].push_back(json::parse(R"({"name": "crate", "box": {"min": [0.2, 0.7, 0.2], "max": [0.3, 0.8, 0.3]}, "dynamic": true, "density": 500})"));
  body["simulation"]["domain"] = {{"min", {-0.1, -0.1, -0.1}}, {"max", {0.7, 0.6, 0.7}}};
  EXPECT_NE(test::sceneErrorOf(body).find("simulation.domain: the dynamic body 'crate' (boundaries[1]) starts outside it"), std::string::npos)
      << test::sceneErrorOf(body);
  // Through the CLI: exit 2 with one line.
  const std::string dir = tempDir("consph_input_domain");
  expectRefused(runScene(dir, below.dump(), ""), "particles start outside the domain");
  EXPECT_EQ(test::sceneErrorOf(test::tinyTankScene(0.01)), "(no error)");
}

TEST(InputFailures, OversizedScenesAreRefusedUpFrontAndMaxParticlesSetsTheLimit) {
  const std::string dir = tempDir("consph_input_size");
  json scene = tinyScene();
  scene["fluids"][0]["blocks"][0]["max"] = {1e12, 0.5, 0.5};
  expectRefused(runScene(dir, scene.dump(), ""), "more than a 32-bit index holds");
  scene = tinyScene();
  scene["fluids"][0]["blocks"][0]["max"] = {100, 100, 10};  // ~1e9 particles
  const auto r = runScene(dir, scene.dump(), "");
  expectRefused(r, "raise it with --max-particles N or simulation.maxParticles");
  EXPECT_NE(r.output.find("half this machine's memory"), std::string::npos) << r.output;
  expectRefused(runScene(dir, tinyScene().dump(), "--max-particles 100"), "more than the limit of 100 particles");
  EXPECT_EQ(runScene(dir, tinyScene().dump(), "--max-particles 10000").status, 0);
}

TEST(InputFailures, SceneErrorsNameTheFileAndTheJsonPath) {
  // The scene file before the JSON path, also for errors found when the simulation is built
  // (an unknown plugin) and for a check of the scene's meaning (the same boundary twice).
  const std::string dir = tempDir("consph_input_names_file");
  json scene = tinyScene();
  scene["fluids"][0]["forces"] = nullptr;
  expectRefused(runScene(dir, scene.dump(), ""), dir + "/scene.json: fluids[0].forces: expected an array of force objects, got null");
  scene = tinyScene();
  scene["simulation"]["pressureSolver"] = "NoSuchSolver";
  expectRefused(runScene(dir, scene.dump(), ""), dir + "/scene.json: simulation.pressureSolver.type: unknown pressure solver 'NoSuchSolver'");
  scene = tinyScene();
  scene["boundaries"].push_back(scene["boundaries"][0]);
  expectRefused(runScene(dir, scene.dump(), ""), dir + "/scene.json: boundaries[1]: the same object as boundaries[0]");
}
