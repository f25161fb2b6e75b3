// The volume-map cache (Boundary/VolumeMapCache.h): a scene's second build loads its maps, with
// the same node values; anything that changes a map misses; a damaged file is rebuilt.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "Boundary/VolumeMapBoundary_Bender2019.h"
#include "TestUtil.h"

using namespace consph;
using namespace consph::test;

namespace {

// A sphere mesh (a real mesh: distances from triangles, winding numbers) in a box tank.
json cachedScene(const std::string& cache, double cellSize = 2.0) {
  json scene = json::parse(R"({
    "simulation": {"particleRadius": 0.025, "boundaryModel": {"type": "VolumeMap"}},
    "fluids": [{"blocks": [{"min": [0.05, 0.05, 0.05], "max": [0.3, 0.2, 0.3]}]}],
    "boundaries": [{"box": {"min": [0, 0, 0], "max": [1, 1, 1]}, "inverted": true},
                   {"name": "ball", "mesh": "../meshes/sphere.obj", "scale": [0.15, 0.15, 0.15], "translation": [0.6, 0.5, 0.5]}]
  })");
  scene["simulation"]["boundaryModel"]["cache"] = cache;
  scene["simulation"]["boundaryModel"]["cellSize"] = cellSize;
  return scene;
}

const VolumeMapBoundary_Bender2019& mapsOf(const Simulation& sim) {
  return dynamic_cast<const VolumeMapBoundary_Bender2019&>(sim.boundaryModel());
}

std::string scratchCache(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("consph_test_volume_map_cache_" + name);
  std::filesystem::remove_all(dir);
  return dir.string();
}

}  // namespace

TEST(VolumeMapCache, SecondBuildLoadsIdenticalMaps) {
  const std::string cache = scratchCache("hit");
  CapturedLog firstLog, secondLog;
  auto first = simulationFromJson(cachedScene(cache), firstLog.sink());
  const auto& built = mapsOf(*first);
  EXPECT_EQ(built.cache().loads(), 0u);
  EXPECT_GE(built.cache().builds(), 7u);  // the tank's six walls and the ball
  const std::size_t files = std::distance(std::filesystem::directory_iterator(cache), std::filesystem::directory_iterator());
  EXPECT_EQ(files, built.cache().builds());

  auto second = simulationFromJson(cachedScene(cache), secondLog.sink());
  const auto& loaded = mapsOf(*second);
  EXPECT_EQ(loaded.cache().builds(), 0u);
  EXPECT_EQ(loaded.cache().loads(), built.cache().builds());
  bool said = false;
  for (const std::string& line : secondLog.infos) said |= line.find("volume map of 'ball' (boundaries[1]): loaded from " + cache) == 0;
  EXPECT_TRUE(said) << "the log names the load";
  ASSERT_EQ(loaded.mapCount(), built.mapCount());
  for (std::size_t m = 0; m < built.mapCount(); ++m) {
    EXPECT_EQ(loaded.pieceMap(m).distances(), built.pieceMap(m).distances()) << "map " << m;
    EXPECT_EQ(loaded.pieceMap(m).volumes(), built.pieceMap(m).volumes()) << "map " << m;
    EXPECT_EQ(loaded.pieceMap(m).surfaceOffset(), built.pieceMap(m).surfaceOffset());
  }
  // The simulations agree too: a step from loaded maps equals one from built ones.
  first->step();
  second->step();
  EXPECT_EQ(first->fluid().positions, second->fluid().positions);
  std::filesystem::remove_all(cache);
}

TEST(VolumeMapCache, ChangedParametersOrTransformsMissAndDamagedFilesAreRebuilt) {
  const std::string cache = scratchCache("miss");
  simulationFromJson(cachedScene(cache));
  // Another cell size: every map differs.
  auto coarser = simulationFromJson(cachedScene(cache, 3.0));
  EXPECT_EQ(mapsOf(*coarser).cache().loads(), 0u);
  // The ball made thicker (mapThickness): its map misses, the tank's six walls still load.
  json thicker = cachedScene(cache);
  thicker["boundaries"][1]["mapThickness"] = 0.01;
  auto thick = simulationFromJson(thicker);
  EXPECT_EQ(mapsOf(*thick).cache().loads(), 6u);
  EXPECT_EQ(mapsOf(*thick).map(1).thickness(), Real(0.01));
  // The ball moved: its map misses, the tank's still loads.
  json moved = cachedScene(cache);
  moved["boundaries"][1]["translation"][0] = 0.55;
  auto shifted = simulationFromJson(moved);
  EXPECT_GE(mapsOf(*shifted).cache().loads(), 1u);
  EXPECT_GE(mapsOf(*shifted).cache().builds(), 1u);
  // A damaged file (cut short): a warning, then the map is built and stored again.
  for (const auto& e : std::filesystem::directory_iterator(cache)) std::filesystem::resize_file(e.path(), 100);
  CapturedLog log;
  auto rebuilt = simulationFromJson(cachedScene(cache), log.sink());
  EXPECT_EQ(mapsOf(*rebuilt).cache().loads(), 0u);
  ASSERT_FALSE(log.warnings.empty());
  EXPECT_NE(log.warnings[0].find("volume map cache:"), std::string::npos) << log.warnings[0];
  EXPECT_EQ(mapsOf(*simulationFromJson(cachedScene(cache))).cache().builds(), 0u);  // stored again
  std::filesystem::remove_all(cache);
}

// A format change leaves maps that could never load: storing a map removes them (files named as
// an older version wrote them), and nothing else in the folder.
TEST(VolumeMapCache, StoringAMapRemovesMapsOfOlderFormatsOnly) {
  const std::string cache = scratchCache("formats");
  std::filesystem::create_directories(cache);
  const std::vector<std::string> old = {"volumemap_0123456789abcdef.state", "volumemap_v2_0123456789abcdef.state"};
  const std::vector<std::string> kept = {"notes.txt", "volumemap_mine.state", "volumemap_v2_short.state", "volumemap_vx_0123456789abcdef.state"};
  for (const auto& name : old) std::ofstream(cache + "/" + name) << "old";
  for (const auto& name : kept) std::ofstream(cache + "/" + name) << "mine";
  CapturedLog log;
  auto sim = simulationFromJson(cachedScene(cache), log.sink());
  for (const auto& name : old) EXPECT_FALSE(std::filesystem::exists(cache + "/" + name)) << name;
  for (const auto& name : kept) EXPECT_TRUE(std::filesystem::exists(cache + "/" + name)) << name;
  const std::string stored = mapsOf(*sim).cache().pathOf(sim->scene().boundaries[1], sim->kernel(), Real(0.05), 0);
  EXPECT_NE(std::filesystem::path(stored).filename().string().rfind("volumemap_v", 0), std::string::npos);
  bool said = false;
  for (const std::string& line : log.infos) said |= line.find("removed 2 map(s) of an older format") != std::string::npos;
  EXPECT_TRUE(said);
  std::filesystem::remove_all(cache);
}

TEST(VolumeMapCache, EmptyCacheFolderTurnsItOff) {
  auto sim = simulationFromJson(cachedScene(""));
  EXPECT_EQ(mapsOf(*sim).cache().loads(), 0u);
  EXPECT_EQ(mapsOf(*sim).cache().pathOf(sim->scene().boundaries[1], sim->kernel(), 0.05, 0), "");
}
