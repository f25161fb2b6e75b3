// Point files a fluid can start from (issue 18): PLY (ASCII, binary of both byte orders), VTU as
// consph writes it, BGEO in Houdini's classic layout (plain and gzip), each written here byte by
// byte from the format's description, plus a .bgeo partio wrote (SPlisHSPlasH's sphere.bgeo).
#include <gtest/gtest.h>
#include <zlib.h>

#include <algorithm>
#include <bit>
#include <cstring>
#include <fstream>

#include "CliUtil.h"
#include "TestUtil.h"
#include "Utilities/Error.h"
#include "Utilities/PointFile.h"
#include "Utilities/VtkWriter.h"

using namespace consph;

namespace {

const std::vector<Vector3r> kPositions = {Vector3r(0.1, 0.2, 0.3), Vector3r(-1, 2.5, 0), Vector3r(4, -5, 6.25)};
const std::vector<Vector3r> kVelocities = {Vector3r(1, 0, 0), Vector3r(0, -2, 0), Vector3r(0.5, 0.5, -3)};

void writeFile(const std::string& path, const std::string& bytes) { std::ofstream(path, std::ios::binary) << bytes; }

// `value`'s bytes in the given byte order.
template <class T>
std::string bytesOf(T value, bool bigEndian) {
  char raw[sizeof(T)];
  std::memcpy(raw, &value, sizeof(T));
  if (bigEndian != (std::endian::native == std::endian::big)) std::reverse(raw, raw + sizeof(T));
  return std::string(raw, sizeof(T));
}

std::string plyHeader(const std::string& format) {
  return "ply\nformat " + format +
         " 1.0\ncomment written by test_point_file\nelement vertex 3\nproperty double x\nproperty double y\nproperty double z\n"
         "property float vx\nproperty float vy\nproperty float vz\nproperty uchar red\nelement face 1\n"
         "property list uchar int vertex_indices\nend_header\n";
}

std::string binaryPly(bool bigEndian) {
  std::string s = plyHeader(bigEndian ? "binary_big_endian" : "binary_little_endian");
  for (std::size_t i = 0; i < kPositions.size(); ++i) {
    for (int c = 0; c < 3; ++c) s += bytesOf(double(kPositions[i][c]), bigEndian);
    for (int c = 0; c < 3; ++c) s += bytesOf(float(kVelocities[i][c]), bigEndian);
    s += bytesOf(std::uint8_t(200), bigEndian);
  }
  s += bytesOf(std::uint8_t(3), bigEndian);
  for (int v = 0; v < 3; ++v) s += bytesOf(std::int32_t(v), bigEndian);
  return s;
}

// Houdini's classic .bgeo (version 5): header, point attributes "v" (vector 3) and "id" (int),
// then x y z w and the attributes per point, big-endian; one empty primitive section follows.
std::string bgeo() {
  std::string s = "BgeoV" + bytesOf(std::int32_t(5), true);
  for (std::int32_t c : {3, 0, 0, 0, 2, 0, 0, 0}) s += bytesOf(c, true);
  auto attribute = [&](const std::string& name, std::int16_t size, std::int32_t type) {
    s += bytesOf(std::int16_t(name.size()), true) + name + bytesOf(size, true) + bytesOf(type, true);
    for (int k = 0; k < size; ++k) s += bytesOf(std::int32_t(0), true);  // defaults
  };
  attribute("v", 3, 5);
  attribute("id", 1, 1);
  for (std::size_t i = 0; i < kPositions.size(); ++i) {
    for (int c = 0; c < 3; ++c) s += bytesOf(float(kPositions[i][c]), true);
    s += bytesOf(1.0f, true);
    for (int c = 0; c < 3; ++c) s += bytesOf(float(kVelocities[i][c]), true);
    s += bytesOf(std::int32_t(i), true);
  }
  return s;
}

void gzipFile(const std::string& path, const std::string& bytes) {
  gzFile f = gzopen(path.c_str(), "wb");
  ASSERT_NE(f, nullptr);
  ASSERT_EQ(gzwrite(f, bytes.data(), unsigned(bytes.size())), int(bytes.size()));
  gzclose(f);
}

void expectPoints(const PointFile& p, double tolerance, bool velocities = true) {
  ASSERT_EQ(p.positions.size(), kPositions.size());
  for (std::size_t i = 0; i < kPositions.size(); ++i) EXPECT_LE((p.positions[i] - kPositions[i]).norm(), tolerance) << i;
  if (!velocities) return;
  ASSERT_EQ(p.velocities.size(), kVelocities.size());
  for (std::size_t i = 0; i < kVelocities.size(); ++i) EXPECT_LE((p.velocities[i] - kVelocities[i]).norm(), 1e-6) << i;
}

}  // namespace

TEST(PointFile, PlyAsciiAndBinaryOfBothByteOrders) {
  const std::string dir = test::tempDir("consph_point_file_ply");
  std::string ascii = plyHeader("ascii");
  for (std::size_t i = 0; i < kPositions.size(); ++i)
    ascii += std::to_string(kPositions[i][0]) + " " + std::to_string(kPositions[i][1]) + " " + std::to_string(kPositions[i][2]) + " " +
             std::to_string(kVelocities[i][0]) + " " + std::to_string(kVelocities[i][1]) + " " + std::to_string(kVelocities[i][2]) + " 7\n";
  ascii += "3 0 1 2\n";
  writeFile(dir + "/a.ply", ascii);
  expectPoints(readPointFile(dir + "/a.ply"), 1e-6);
  writeFile(dir + "/le.ply", binaryPly(false));
  expectPoints(readPointFile(dir + "/le.ply"), 1e-12);
  writeFile(dir + "/be.PLY", binaryPly(true));
  expectPoints(readPointFile(dir + "/be.PLY"), 1e-12);
  // Without vx, vy, vz: positions only.
  writeFile(dir + "/p.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n1 2 3\n");
  const PointFile p = readPointFile(dir + "/p.ply");
  EXPECT_EQ(p.positions.at(0), Vector3r(1, 2, 3));
  EXPECT_TRUE(p.velocities.empty());
}

TEST(PointFile, VtuAsConsphWritesIt) {
  const std::string dir = test::tempDir("consph_point_file_vtu");
  VtuPointCloud cloud(kPositions.data(), kPositions.size());
  cloud.add("velocity", kVelocities[0].data(), 3);
  writeFile(dir + "/frame.vtu", cloud.serialize());
  expectPoints(readPointFile(dir + "/frame.vtu"), 0);
}

TEST(PointFile, BgeoPlainGzippedAndPartiosOwn) {
  const std::string dir = test::tempDir("consph_point_file_bgeo");
  writeFile(dir + "/plain.bgeo", bgeo());
  expectPoints(readPointFile(dir + "/plain.bgeo"), 1e-6);
  gzipFile(dir + "/zipped.bgeo", bgeo());
  expectPoints(readPointFile(dir + "/zipped.bgeo"), 1e-6);
  // SPlisHSPlasH's sphere.bgeo (written by partio, gzip): 12 394 samples of the unit sphere.
  const PointFile sphere = readPointFile(test::dataPath("splishsplash/models/sphere.bgeo"));
  ASSERT_EQ(sphere.positions.size(), 12394u);
  for (const Vector3r& x : sphere.positions) {
    EXPECT_GT(x.norm(), Real(0.98));
    EXPECT_LT(x.norm(), Real(1.0001));
  }
  EXPECT_TRUE(sphere.velocities.empty());  // its attributes are pscale and id
}

TEST(PointFile, BadFilesNameThemselves) {
  const std::string dir = test::tempDir("consph_point_file_bad");
  auto errorOf = [](const std::string& path) {
    try {
      readPointFile(path);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  EXPECT_EQ(errorOf(dir + "/x.xyz"), dir + "/x.xyz: point files are .ply, .vtu or .bgeo");
  EXPECT_EQ(errorOf(dir + "/missing.ply"), dir + "/missing.ply: cannot open the point file");
  std::string truncated = binaryPly(false);
  writeFile(dir + "/short.ply", truncated.substr(0, truncated.size() - 40));
  EXPECT_EQ(errorOf(dir + "/short.ply"), dir + "/short.ply: the file ends early (truncated?)");
  writeFile(dir + "/short.bgeo", bgeo().substr(0, 80));
  EXPECT_EQ(errorOf(dir + "/short.bgeo"), dir + "/short.bgeo: the file ends early (truncated?)");
  writeFile(dir + "/text.bgeo", "PGEOMETRY V5\n");
  EXPECT_NE(errorOf(dir + "/text.bgeo").find("not a Houdini .bgeo file"), std::string::npos);
}
