// Frames that consph writes (Simulation::exportFrame, Simulation/FrameSeries.h) read back by
// consph's own point-file reader (Utilities/PointFile.h, written from partio's and the PLY/VTU
// layouts for starting a fluid from a file): a frame can seed the next run. The formats' own
// layouts are checked by independent readers in tests/python/test_frame_formats.py.
#include <gtest/gtest.h>

#include <filesystem>

#include "TestUtil.h"
#include "Utilities/PointFile.h"

using namespace consph;
using namespace consph::test;

TEST(FrameExport, FramesReadBackAsPointFiles) {
  auto sim = simulationFromJson(tinyTankScene(1));
  for (int s = 0; s < 5; ++s) sim->step();
  const FluidModel& f = sim->fluid();
  const auto dir = std::filesystem::temp_directory_path() / "consph_test_frame_export";
  std::filesystem::create_directories(dir);
  // Not .bgeo.gz: readPointFile takes gzip data, but only under a .bgeo name.
  for (const char* name : {"f.bgeo", "f.vtu", "f.ply"}) {
    const std::string path = (dir / name).string();
    sim->exportFrame(path);
    const PointFile points = readPointFile(path);
    ASSERT_EQ(points.positions.size(), f.size()) << name;
    const bool bgeo = std::string(name).find(".bgeo") != std::string::npos;  // float32 always
    for (std::size_t i = 0; i < f.size(); ++i) {
      for (int c = 0; c < 3; ++c) {
        const double x = f.positions[i][c], v = f.velocities[i][c];
        EXPECT_EQ(double(points.positions[i][c]), bgeo ? double(float(x)) : x) << name << " particle " << i;
        if (!points.velocities.empty()) {
          EXPECT_EQ(double(points.velocities[i][c]), bgeo ? double(float(v)) : v) << name << " particle " << i;
        }
      }
    }
    if (bgeo) {
      EXPECT_EQ(points.velocities.size(), f.size()) << "Houdini's v attribute";
    }
  }
  std::filesystem::remove_all(dir);
}
