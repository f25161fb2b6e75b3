// Fields registered by force plugins go through the generic ParticleFields machinery: they are
// permuted with the particles on Z-order sorting and written to the .vtu frames, with no
// plugin-specific code in the simulation or the writer.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "Utilities/VtkWriter.h"
#include "tests/physics/ForceTestSupport.h"

using namespace consph;
using namespace consph::test;

namespace {

// The values of one Float64/Float32 point array of a consph .vtu (appended raw, UInt64 headers).
std::vector<double> readVtuArray(const std::string& path, const std::string& name) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string text = ss.str();
  const std::size_t at = text.find("Name=\"" + name + "\"");
  if (at == std::string::npos) return {};
  const std::size_t typeAt = text.rfind("type=\"", at);
  const bool isDouble = text.compare(typeAt + 6, 7, "Float64") == 0;
  const std::size_t offsetAt = text.find("offset=\"", at) + 8;
  const std::size_t offset = std::stoull(text.substr(offsetAt, text.find('"', offsetAt) - offsetAt));
  const std::size_t data = text.find('_', text.find("<AppendedData")) + 1;
  std::uint64_t bytes = 0;
  std::memcpy(&bytes, text.data() + data + offset, 8);
  std::vector<double> out;
  const char* p = text.data() + data + offset + 8;
  for (std::size_t k = 0; k < bytes / (isDouble ? 8 : 4); ++k) {
    if (isDouble) {
      double v;
      std::memcpy(&v, p + 8 * k, 8);
      out.push_back(v);
    } else {
      float v;
      std::memcpy(&v, p + 4 * k, 4);
      out.push_back(v);
    }
  }
  return out;
}

TEST(ForcesFields, PluginFieldIsPermutedOnSortAndExported) {
  // A falling block, re-sorted every step. With inertiaInverse = 0 the micropolar angular
  // velocity never changes (d omega / dt = Theta^-1 (...)), so it must keep the value the test
  // writes: omega_i = (id_i, 0, 0), whatever order the particles are in.
  auto sim = simulationFromJson(R"({"simulation": {"sortInterval": 1},
      "fluids": [{"forces": [{"type": "Micropolar", "inertiaInverse": 0}, {"type": "Akinci2013"}],
                  "blocks": [{"min": [0, 0, 0], "max": [0.3, 0.2, 0.25]}]}]})");
  FluidModel& f = sim->fluid();
  auto& omega = f.fields().get<Vector3r>("angularVelocity");
  for (std::size_t i = 0; i < f.size(); ++i) omega[i] = Vector3r(Real(f.ids[i]), 0, 0);
  for (int s = 0; s < 3; ++s) sim->step();
  std::size_t moved = 0;
  for (std::size_t i = 0; i < f.size(); ++i) {
    moved += f.ids[i] != i;
    EXPECT_EQ(omega[i][0], Real(f.ids[i])) << "particle " << i;
  }
  EXPECT_GT(moved, f.size() / 2) << "the Z-order sort should have reordered the lattice";

  const auto path = (std::filesystem::temp_directory_path() / "consph_test_plugin_fields.vtu").string();
  sim->exportFrame(path);
  const auto exported = readVtuArray(path, "angularVelocity");
  ASSERT_EQ(exported.size(), 3 * f.size());
  for (std::size_t i = 0; i < f.size(); ++i) EXPECT_EQ(exported[3 * i], double(f.ids[i]));
  EXPECT_EQ(readVtuArray(path, "normal").size(), 3 * f.size());
  EXPECT_TRUE(readVtuArray(path, "viscosityVelocityChange").empty());  // never registered here
  std::filesystem::remove(path);
}

TEST(ForcesFields, SceneWithoutForcesExportsNoPluginField) {
  auto sim = simulationFromJson(R"({"fluids": [{"blocks": [{"min": [0, 0, 0], "max": [0.2, 0.2, 0.2]}]}]})");
  sim->step();
  const auto path = (std::filesystem::temp_directory_path() / "consph_test_no_plugin_fields.vtu").string();
  sim->exportFrame(path);
  EXPECT_TRUE(readVtuArray(path, "angularVelocity").empty());
  EXPECT_TRUE(readVtuArray(path, "normal").empty());
  EXPECT_EQ(readVtuArray(path, "velocity").size(), 3 * sim->fluid().size());
  std::filesystem::remove(path);
}

}  // namespace
