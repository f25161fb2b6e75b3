// Checkpoints (Simulation::saveCheckpoint, restoreCheckpoint, output.checkpointInterval): a run
// restarted from one continues bit for bit, with a dynamic body and an emitter in the scene.
#include <gtest/gtest.h>
#include <omp.h>

#include <cstring>
#include <filesystem>
#include <fstream>

#include "TestUtil.h"
#include "Utilities/OutputFolder.h"

using namespace consph;
using namespace consph::test;

namespace {

// A tank with a block of water, a box dropped into it and a jet from above: every kind of
// state a checkpoint holds (fields incl. DFSPH's warm starts, a body, an emitter, sorting).
json checkpointScene() {
  return json::parse(R"({
    "simulation": {"particleRadius": 0.025, "sortInterval": 5, "stopAt": 1,
                   "pressureSolver": {"type": "DFSPH", "maxError": 0.01}},
    "fluids": [{"name": "water", "forces": [{"type": "StandardViscosity", "viscosity": 0.01}],
                "blocks": [{"min": [0.05, 0.05, 0.05], "max": [0.35, 0.25, 0.35]}],
                "emitters": [{"position": [0.3, 0.6, 0.2], "direction": [0, -1, 0], "width": 0.1, "height": 0.1,
                              "speed": 1.0, "start": 0.0, "end": 1.0}]}],
    "boundaries": [{"box": {"min": [0, 0, 0], "max": [0.6, 1.0, 0.4]}, "inverted": true},
                   {"name": "crate", "box": {"min": [0.4, 0.3, 0.1], "max": [0.5, 0.4, 0.2]}, "dynamic": true, "density": 500}]
  })");
}

std::unique_ptr<Simulation> restartedSimulation(json scene, const std::string& checkpoint, const LogSink& log = {}) {
  if (!scene.contains("output")) scene["output"] = {{"enabled", false}};
  SceneDescription description = parseScene(scene, CONSPH_TEST_DATA_DIR "/scenes", log);
  description.restartFrom = checkpoint;
  return std::make_unique<Simulation>(std::move(description), builtinPlugins(),
                                      log ? log : LogSink([](LogLevel, const std::string&) {}));
}

template <class T>
bool sameBits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

// One thread: OpenMP's reductions (the solvers' average density error) combine the threads'
// partial sums in the order they arrive, so only a single thread repeats to the last bit.
struct OneThread {
  int before = omp_get_max_threads();
  OneThread() { omp_set_num_threads(1); }
  ~OneThread() { omp_set_num_threads(before); }
};

std::string scratchDir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("consph_test_checkpoint_" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir.string();
}

// N steps of `scene` equal k steps, a checkpoint, a restart from it and N - k steps, bit for bit.
void restartContinuesBitForBit(const json& scene) {
  constexpr int N = 40, k = 17;  // k is no multiple of sortInterval: the order must survive too
  const std::string path = scratchDir("bits") + "/state.ckpt";

  auto straight = simulationFromJson(scene);
  for (int s = 0; s < N; ++s) straight->step();

  auto first = simulationFromJson(scene);
  for (int s = 0; s < k; ++s) first->step();
  first->saveCheckpoint(path);
  const std::size_t particlesAtK = first->fluid().size();
  first.reset();

  auto restarted = restartedSimulation(scene, path);
  ASSERT_EQ(restarted->stepCount(), std::size_t(k));
  ASSERT_EQ(restarted->fluid().size(), particlesAtK);
  for (int s = k; s < N; ++s) restarted->step();

  // The scene did something in both halves: the jet emitted, the crate fell and rotated or slid.
  EXPECT_GT(straight->fluid().size(), particlesAtK);
  EXPECT_GT(straight->stats().particlesEmitted, 0u);
  const RigidBody& a = test::rigidBodies(*straight)->bodies().at(0);
  const RigidBody& b = test::rigidBodies(*restarted)->bodies().at(0);
  EXPECT_LT(a.v[1], 0);

  EXPECT_EQ(restarted->stepCount(), straight->stepCount());
  EXPECT_EQ(restarted->time(), straight->time());  // exact: == on finite values is bit equality up to the sign of 0
  EXPECT_EQ(restarted->dt(), straight->dt());
  FluidModel& fa = straight->fluid();
  FluidModel& fb = restarted->fluid();
  ASSERT_EQ(fa.size(), fb.size());
  EXPECT_TRUE(sameBits(fa.positions, fb.positions));
  EXPECT_TRUE(sameBits(fa.velocities, fb.velocities));
  EXPECT_TRUE(sameBits(fa.pressures, fb.pressures));
  EXPECT_TRUE(sameBits(fa.ids, fb.ids));
  for (int c = 0; c < 3; ++c) {
    EXPECT_EQ(a.x[c], b.x[c]);
    EXPECT_EQ(a.v[c], b.v[c]);
    EXPECT_EQ(a.w[c], b.w[c]);
  }
  EXPECT_EQ(a.q.coeffs(), b.q.coeffs());
  std::filesystem::remove_all(std::filesystem::path(path).parent_path());
}

}  // namespace

TEST(Checkpoint, RestartContinuesBitForBit) {
  OneThread oneThread;
  // Both step controls: "iterations" carries the last solve's iteration count across the restart.
  for (const char* control : {"cfl", "iterations"}) {
    SCOPED_TRACE(control);
    json scene = checkpointScene();
    scene["simulation"]["timeStepControl"] = control;
    restartContinuesBitForBit(scene);
  }
}

TEST(Checkpoint, IntervalWritesRunFilesAndARestartContinuesTheSeries) {
  OneThread oneThread;
  const std::string dir = scratchDir("interval");
  json scene = checkpointScene();
  scene["output"] = {{"directory", dir + "/out"}, {"fps", 100}, {"checkpointInterval", 0.02}};
  auto run = std::make_unique<Simulation>(parseScene(scene, ".", {}), builtinPlugins(), LogSink([](LogLevel, const std::string&) {}));
  run->run(Real(0.05));
  EXPECT_EQ(run->checkpointsWritten(), 2u);
  for (const char* f : {"checkpoint_00001.state", "checkpoint_00002.state"}) {
    EXPECT_TRUE(std::filesystem::exists(dir + "/out/" + f)) << f;
    EXPECT_TRUE(isRunFile(f)) << f;  // the output folder's owner check counts them
  }
  const std::size_t framesBefore = 6;  // t = 0, 0.01, ..., 0.05
  ASSERT_TRUE(std::filesystem::exists(dir + "/out/water_00005.vtu"));
  run.reset();

  // Restarted into its own folder: refused for a fresh run, its own for the restart; the .pvd
  // keeps the frames up to the checkpoint (t = 0.04) and goes on.
  EXPECT_THROW(Simulation(parseScene(scene, ".", {}), builtinPlugins(), LogSink([](LogLevel, const std::string&) {})), InputError);
  auto restarted = restartedSimulation(scene, dir + "/out/checkpoint_00002.state");
  EXPECT_GE(restarted->time(), Real(0.04) - restarted->dt());
  restarted->run(Real(0.07));
  std::ifstream pvd(dir + "/out/water.pvd");
  const std::string text((std::istreambuf_iterator<char>(pvd)), std::istreambuf_iterator<char>());
  std::size_t listed = 0;
  for (std::size_t at = text.find("<DataSet"); at != std::string::npos; at = text.find("<DataSet", at + 1)) ++listed;
  EXPECT_EQ(listed, framesBefore + 2) << text;  // 0 ... 0.04 from the checkpoint, then 0.05, 0.06, 0.07
  EXPECT_TRUE(std::filesystem::exists(dir + "/out/water_00007.vtu"));
  std::filesystem::remove_all(dir);
}

// probes.csv of a restarted run: the rows up to the checkpoint, then this run's, in time order
// and without a gap or a repeat; rows the first run wrote after its checkpoint are dropped.
TEST(Checkpoint, ARestartKeepsTheProbeRowsUpToItsCheckpoint) {
  // Rows of every step, and rows at a rate whose interval a checkpoint cuts (the load means over
  // the interval since the last row must carry over the restart).
  for (double probeFps : {0.0, 110.0}) {
  SCOPED_TRACE("probeFps " + std::to_string(probeFps));
  OneThread oneThread;
  const std::string dir = scratchDir("probes");
  json scene = checkpointScene();
  scene["output"] = {{"directory", dir + "/out"}, {"fps", 100}, {"checkpointInterval", 0.02}, {"probeFps", probeFps}};
  scene["probes"] = json::parse(R"([{"name": "floor", "kind": "pressure", "position": [0.2, 0, 0.2]},
                                    {"name": "crate", "kind": "force", "boundary": "crate"}])");
  auto readRows = [&]() {
    std::ifstream in(dir + "/out/probes.csv");
    std::vector<std::string> rows;
    for (std::string line; std::getline(in, line);) rows.push_back(line);
    return rows;
  };
  auto straight = std::make_unique<Simulation>(parseScene(scene, ".", {}), builtinPlugins(), LogSink([](LogLevel, const std::string&) {}));
  straight->run(Real(0.07));
  const std::vector<std::string> reference = readRows();
  straight.reset();
  std::filesystem::remove_all(dir + "/out");
  // The first run goes on past its second checkpoint (t = 0.04) to 0.05 and is "killed".
  auto first = std::make_unique<Simulation>(parseScene(scene, ".", {}), builtinPlugins(), LogSink([](LogLevel, const std::string&) {}));
  first->run(Real(0.05));
  const std::size_t rowsWhenKilled = readRows().size();
  first.reset();
  auto restarted = restartedSimulation(scene, dir + "/out/checkpoint_00002.state");
  const Real checkpointTime = restarted->time();
  EXPECT_LT(readRows().size(), rowsWhenKilled);  // the rows after the checkpoint are gone
  restarted->run(Real(0.07));
  const std::vector<std::string> rows = readRows();
  // Bit for bit the same run (one thread), so the same rows as the run that was never stopped.
  EXPECT_EQ(rows, reference);
  ASSERT_GT(rows.size(), 2u);
  EXPECT_EQ(rows[0].rfind("time,floor,crate.fx", 0), 0u) << rows[0];
  std::printf("[ probes ] probeFps %g: %zu rows straight, %zu when killed at t = 0.05, restarted at t = %.4f: %zu rows\n",
              probeFps, reference.size(), rowsWhenKilled, double(checkpointTime), rows.size());
  std::filesystem::remove_all(dir);
  }
}

TEST(Checkpoint, RefusesAnotherSceneNamingTheDifference) {
  const std::string path = scratchDir("mismatch") + "/state.ckpt";
  auto sim = simulationFromJson(checkpointScene());
  sim->step();
  sim->saveCheckpoint(path);
  json other = checkpointScene();
  other["fluids"][0]["blocks"][0]["max"][1] = 0.3;
  try {
    restartedSimulation(other, path);
    FAIL() << "a checkpoint of another scene was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/fluids/0/blocks/0/max/1"), std::string::npos) << e.what();
  }
  // output.* and simulation.stopAt may change.
  json later = checkpointScene();
  later["simulation"]["stopAt"] = 2;
  EXPECT_EQ(restartedSimulation(later, path)->stepCount(), 1u);
  // A file that is no checkpoint.
  std::ofstream(path) << "not a checkpoint";
  EXPECT_THROW(restartedSimulation(checkpointScene(), path), InputError);
  std::filesystem::remove_all(std::filesystem::path(path).parent_path());
}
