// A fluid that starts from a point file (fluids[].particleFiles) or from a closed mesh's volume
// (fluids[].meshVolumes), with transforms; and SPlisHSPlasH's FluidModels mapped to them.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "CliUtil.h"
#include "Simulation/SplishSplashScene.h"
#include "TestUtil.h"
#include "Utilities/PlyWriter.h"
#include "Utilities/PointFile.h"

using namespace consph;

namespace {

// A scene whose one fluid comes from `sources` (e.g. {"particleFiles": [...]}), r = 0.02, no walls.
json sceneWith(const json& sources) {
  json fluid = sources;
  fluid["name"] = "water";
  return {{"simulation", {{"particleRadius", 0.02}, {"gravity", {0, 0, 0}}}}, {"fluids", {fluid}}, {"output", {{"enabled", false}}}};
}

SceneDescription parse(const json& scene, const std::string& baseDir, test::CapturedLog& log) { return parseScene(scene, baseDir, log.sink()); }

void boundsOf(const std::vector<Vector3r>& x, Vector3r& lo, Vector3r& hi) {
  lo = hi = x.at(0);
  for (const Vector3r& p : x) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
}

}  // namespace

// consph's own PLY frames (binary, velocity as velocity_x velocity_y velocity_z) read back as a
// particle file with their velocities, in both precisions.
TEST(FluidSources, APlyFrameReadsBackWithItsVelocities) {
  const std::string dir = test::tempDir("consph_fluid_sources_ply_frame");
  const std::vector<Vector3r> x = {Vector3r(0.5, 0.25, 1), Vector3r(-1, 2, 0.125)}, v = {Vector3r(1, -2, 0.5), Vector3r(0, 0.25, -4)};
  PointTable table;
  table.positions = x.data();
  table.size = x.size();
  table.addReal("velocity", reinterpret_cast<const Real*>(v.data()), 3);
  for (FramePrecision precision : {FramePrecision::Float, FramePrecision::Double}) {
    const std::string path = dir + "/frame.ply";
    std::ofstream(path, std::ios::binary) << serializePly(table, precision);
    const PointFile read = readPointFile(path);
    ASSERT_EQ(read.positions.size(), 2u);
    ASSERT_EQ(read.velocities.size(), 2u) << "velocity_x/_y/_z not read";
    for (std::size_t i = 0; i < 2; ++i) {
      EXPECT_EQ(read.positions[i], x[i]);  // all values exact in float
      EXPECT_EQ(read.velocities[i], v[i]);
    }
  }
}

TEST(FluidSources, ParticleFileIsPlacedByItsTransform) {
  const std::string dir = test::tempDir("consph_fluid_sources_file");
  std::ofstream(dir + "/drop.ply") << "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
                                      "property float vx\nproperty float vy\nproperty float vz\nend_header\n1 0 0 1 0 0\n0 1 0 0 0 2\n";
  test::CapturedLog log;
  // Scaled by 2 along x, turned a quarter about z, moved up 1 m: (1,0,0) -> (0,2,1), (0,1,0) -> (-1,0,1).
  json scene = sceneWith({{"particleFiles",
                           {{{"file", "drop.ply"}, {"scale", {2, 1, 1}}, {"rotationAxis", {0, 0, 1}}, {"rotationAngle", M_PI / 2},
                             {"translation", {0, 0, 1}}}}}});
  SceneDescription s = parse(scene, dir, log);
  const FluidDescription& f = s.fluids.at(0);
  ASSERT_EQ(f.sourcePositions.size(), 2u);
  EXPECT_TRUE(f.sourcePositions[0].isApprox(Vector3r(0, 2, 1), Real(1e-6))) << f.sourcePositions[0].transpose();
  EXPECT_TRUE(f.sourcePositions[1].isApprox(Vector3r(-1, 0, 1), Real(1e-6))) << f.sourcePositions[1].transpose();
  // The file's velocities turn with the particles; "velocity" replaces them.
  EXPECT_TRUE(f.sourceVelocities[0].isApprox(Vector3r(0, 1, 0), Real(1e-6)));
  EXPECT_TRUE(f.sourceVelocities[1].isApprox(Vector3r(0, 0, 2), Real(1e-6)));
  scene["fluids"][0]["particleFiles"][0]["velocity"] = {3, 0, 0};
  EXPECT_EQ(parse(scene, dir, log).fluids[0].sourceVelocities[1], Vector3r(3, 0, 0));
  EXPECT_TRUE(log.warnings.empty());
  // The simulation starts with them, each of the lattice particles' mass.
  Simulation sim(parse(scene, dir, log), builtinPlugins(), log.sink());
  ASSERT_EQ(sim.fluid().size(), 2u);
  EXPECT_NEAR(double(sim.fluid().masses[0]), 1000 * std::pow(double(sim.scene().particleSpacing) * 0.02, 3), test::fewUlps(1e-12, 0.05));
  // A missing file names the JSON path's file.
  scene["fluids"][0]["particleFiles"][0]["file"] = "nothing.bgeo";
  EXPECT_NE(test::sceneErrorOf(scene).find("nothing.bgeo: cannot open the point file"), std::string::npos) << test::sceneErrorOf(scene);
}

TEST(FluidSources, MeshVolumeOnConsphsLatticeMatchesABlock) {
  test::CapturedLog log;
  // UnitBox.obj scaled to a 0.4 m cube at [1, 0, 0]: the same particles as a 0.4 m block there.
  const json scene = sceneWith({{"meshVolumes", {{{"mesh", "UnitBox.obj"}, {"scale", {0.4, 0.4, 0.4}}, {"translation", {1.2, 0.2, 0.2}}}}}});
  const SceneDescription s = parse(scene, test::dataPath("meshes"), log);
  const auto& x = s.fluids[0].sourcePositions;
  FluidBlock block{Vector3r(1, 0, 0), Vector3r(Real(1.4), Real(0.4), Real(0.4)), Vector3r::Zero(), BlockLattice::CellCentred};
  std::vector<Vector3r> expected;
  sampleBlock(block, s.particleSpacing * s.particleRadius, s.particleRadius, expected);
  ASSERT_EQ(x.size(), expected.size());
  EXPECT_EQ(x.size(), 1000u);  // floor(0.4 / (1.8566 0.02)) = 10 per axis
  for (std::size_t i = 0; i < x.size(); ++i) EXPECT_LE((x[i] - expected[i]).norm(), 1e-9) << i;
}

TEST(FluidSources, MeshVolumeOnSplishSplashsLatticeIsSampledInTheMeshsFrame) {
  test::CapturedLog log;
  // A 0.41 x 0.21 x 0.21 box: SPlisHSPlasH's 2r voxel centres in the scaled mesh's frame, from
  // -0.205 + r on (10 x 5 x 5 inside), then turned a quarter about z ((x, y) -> (-y, x)) and moved
  // to x = 1.
  const json scene = sceneWith({{"meshVolumes",
                                 {{{"mesh", "UnitBox.obj"}, {"lattice", "splishsplashRegular"}, {"scale", {0.41, 0.21, 0.21}},
                                   {"rotationAxis", {0, 0, 1}}, {"rotationAngle", M_PI / 2}, {"translation", {1, 0, 0}}, {"velocity", {0, -1, 0}}}}}});
  const SceneDescription s = parse(scene, test::dataPath("meshes"), log);
  const auto& x = s.fluids[0].sourcePositions;
  ASSERT_EQ(x.size(), 250u);
  Vector3r lo, hi;
  boundsOf(x, lo, hi);
  EXPECT_LE((lo - Vector3r(Real(0.925), Real(-0.185), Real(-0.085))).norm(), test::fewUlps(1e-9, 1)) << lo.transpose();
  EXPECT_LE((hi - Vector3r(Real(1.085), Real(0.175), Real(0.075))).norm(), test::fewUlps(1e-9, 1)) << hi.transpose();
  EXPECT_EQ(s.fluids[0].sourceVelocities.at(7), Vector3r(0, -1, 0));
  // A sphere's volume: about its volume / (2r)^3 particles.
  const json sphere = sceneWith({{"meshVolumes", {{{"mesh", "sphere.obj"}, {"lattice", "splishsplashRegular"}, {"scale", {0.2, 0.2, 0.2}}}}}});
  const double n = double(parse(sphere, test::dataPath("meshes"), log).fluids[0].sourcePositions.size());
  EXPECT_NEAR(n, 4.0 / 3 * M_PI * 0.008 / std::pow(0.04, 3), 0.06 * n);
}

TEST(FluidSources, OpenMeshesAndEmptyVolumesAreRefused) {
  const std::string dir = test::tempDir("consph_fluid_sources_open");
  std::ofstream(dir + "/sheet.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  json scene = sceneWith({{"meshVolumes", {{{"mesh", dir + "/sheet.obj"}}}}});
  EXPECT_NE(test::sceneErrorOf(scene).find("fluids[0].meshVolumes[0].mesh: a fluid volume needs a closed mesh"), std::string::npos)
      << test::sceneErrorOf(scene);
  scene = sceneWith({{"meshVolumes", {{{"mesh", "../meshes/UnitBox.obj"}, {"scale", {0.001, 0.001, 0.001}}}}}});
  EXPECT_NE(test::sceneErrorOf(scene).find("no lattice point lies inside the mesh"), std::string::npos) << test::sceneErrorOf(scene);
  scene = sceneWith({{"meshVolumes", {{{"mesh", "../meshes/UnitBox.obj"}, {"lattice", "splishsplashDense"}}}}});
  EXPECT_NE(test::sceneErrorOf(scene).find("fluids[0].meshVolumes[0].lattice"), std::string::npos) << test::sceneErrorOf(scene);
}

TEST(FluidSources, SplishSplashFluidModelsMapAndRun) {
  // A particle file (partio's sphere.bgeo) and a closed mesh, as SPlisHSPlasH tells them apart.
  json splishsplash = json::parse(R"({
    "Configuration": {"particleRadius": 0.025, "boundaryHandlingMethod": 0},
    "FluidModels": [
      {"particleFile": "../models/sphere.bgeo", "translation": [0, 1, 0], "scale": [0.5, 0.5, 0.5], "initialVelocity": [0, -1, 0]},
      {"particleFile": "../models/UnitBox.obj", "translation": [0, 0.3, 0], "scale": [0.4, 0.4, 0.4], "resolutionSDF": [20, 20, 20]}
    ],
    "RigidBodies": [{"geometryFile": "../models/UnitBox.obj", "translation": [0, 1, 0], "scale": [2, 2, 2], "mapInvert": true}]
  })");
  test::CapturedLog log;
  const std::string scenes = test::dataPath("splishsplash/scenes");
  json converted = convertSplishSplashScene(splishsplash, scenes, scenes, "models", log.sink());
  const json& fluid = converted["fluids"][0];
  EXPECT_EQ(fluid["particleFiles"][0]["file"], "../models/sphere.bgeo");
  EXPECT_EQ(fluid["meshVolumes"][0]["lattice"], "splishsplashRegular");
  ASSERT_EQ(log.warnings.size(), 1u);
  EXPECT_NE(log.warnings[0].find("'resolutionSDF'"), std::string::npos) << log.warnings[0];
  const SceneDescription s = parseScene(converted, scenes, log.sink());
  const auto& x = s.fluids[0].sourcePositions;
  // 12 394 points on a sphere of radius 0.5 about (0, 1, 0), then the box's 0.4 m cube: 8^3 voxel
  // centres 2r apart from -0.2 + r.
  ASSERT_EQ(x.size(), 12394u + 512u);
  EXPECT_NEAR(double((x[0] - Vector3r(0, 1, 0)).norm()), 0.5, 0.01);
  EXPECT_EQ(s.fluids[0].sourceVelocities[0], Vector3r(0, -1, 0));

  // The mesh's volume alone runs in the tank (the sphere's samples are a surface, not a fluid).
  splishsplash["FluidModels"].erase(0);
  converted = convertSplishSplashScene(splishsplash, scenes, scenes, "models", log.sink());
  converted["output"] = {{"enabled", false}};
  Simulation sim(parseScene(converted, scenes, log.sink()), builtinPlugins(), log.sink());
  ASSERT_EQ(sim.fluid().size(), 512u);
  sim.run(Real(0.01));
  EXPECT_GE(sim.stepCount(), 2u);
  EXPECT_EQ(sim.fluid().size(), 512u);
}
