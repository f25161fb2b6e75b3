// Volume maps (Bender et al. 2019): the signed distance and boundary volume on the grid, and the
// virtual boundary particles the VolumeMap boundary model builds from them.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <numbers>

#include "Boundary/VolumeMap.h"
#include "Boundary/VolumeMapBoundary_Bender2019.h"
#include "Simulation/PluginRegistry.h"
#include "Simulation/Simulation.h"
#include "Utilities/TriangleMesh.h"
#include "TestUtil.h"

using namespace consph;

namespace {

constexpr Real kR = Real(0.025);

BoundaryObject boxObject(const Vector3r& lo, const Vector3r& hi, bool inverted) {
  BoundaryObject o;
  o.name = o.path = "box";
  o.isBox = true;
  o.inverted = inverted;
  o.boxMin = lo;
  o.boxMax = hi;
  o.mesh = makeBoxMesh(lo, hi, inverted);
  return o;
}

}  // namespace

// On a flat floor the map's nodes carry the half-space volume of the 1-D integral (the ball
// quadrature against Simpson's rule), Phi is the height and the normal points up.
TEST(VolumeMap, FloorVolumeIsTheHalfSpaceIntegral) {
  const CubicSplineKernel kernel(4 * kR);
  const VolumeMap map(boxObject(Vector3r::Zero(), Vector3r(1, 1, 1), true), kernel, kR);
  for (int k = 0; k < 4; ++k) {
    const Real y = Real(k) * kR;  // grid nodes: the grid starts a whole number of cells below 0
    Real phi, volume;
    Vector3r phiGradient, volumeGradient;
    ASSERT_TRUE(map.sample(Vector3r(Real(0.5), y, Real(0.5)), phi, phiGradient, volume, volumeGradient));
    EXPECT_NEAR(phi, y, 1e-6);
    EXPECT_NEAR((phiGradient - Vector3r::UnitY()).norm(), 0, 1e-5);
    const Real exact = VolumeMap::halfSpaceVolume(kernel, y);
    EXPECT_NEAR(volume / exact, 1, 2e-4) << "y = " << k << " r";
    EXPECT_LT(volumeGradient[1], 0);  // the boundary volume falls away from the wall
  }
  // Out of reach from h on; a deep-solid point carries the whole ball.
  Real phi, volume;
  Vector3r normal, gradient;
  EXPECT_FALSE(map.sample(Vector3r(Real(0.5), Real(4.2) * kR, Real(0.5)), phi, normal, volume, gradient));
  EXPECT_NEAR(VolumeMap::halfSpaceVolume(kernel, -4 * kR) / (Real(0.8 * 4.0 / 3.0) * std::numbers::pi_v<Real> * std::pow(4 * kR, 3)), 1, 1e-5);
}

// The rest distance the offset is computed from: where the first layer of the default lattice
// has rest density (measured in a settled column: 2.29-2.36 r).
TEST(VolumeMap, RestDistanceOfTheDefaultLattice) {
  const CubicSplineKernel kernel(4 * kR);
  const Real d = VolumeMap::restDistance(kernel, kR, Real(1.8566) * kR) / kR;
  EXPECT_NEAR(d, 2.28, 0.02);
}

// A box given as a mesh (distances from its triangles) against the analytic box, with fine cells
// (0.5 r): the volume quadrature of nodes inside the solid reaches 2h deep, which the exact band
// must cover (with a band of h + 5 cells, solid 2-3 r deep read as fluid: V 4-16 % low).
TEST(VolumeMap, MeshAndAnalyticBoxAgreeWithFineCells) {
  const CubicSplineKernel kernel(4 * kR);
  BoundaryObject analytic = boxObject(Vector3r::Zero(), Vector3r(Real(0.6), Real(0.6), Real(0.6)), true), mesh = analytic;
  mesh.isBox = false;
  const VolumeMap a(analytic, kernel, Real(0.5) * kR), m(mesh, kernel, Real(0.5) * kR);
  for (Real y : {Real(-3), Real(-2), Real(-0.5), Real(0.7), Real(2.3), Real(3.5)}) {
    Real phiA, volA, phiM, volM;
    Vector3r gA, gvA, gM, gvM;
    const Vector3r x(Real(0.3), y * kR, Real(0.31));
    ASSERT_TRUE(a.sample(x, phiA, gA, volA, gvA));
    ASSERT_TRUE(m.sample(x, phiM, gM, volM, gvM)) << y;
    EXPECT_NEAR(phiM, phiA, 1e-5) << y;
    EXPECT_NEAR(volM / volA, 1, 1e-3) << y;
    EXPECT_LT(gvM[1], 0) << y;  // the volume falls away from the wall, also deep in the solid
  }
}

// A plate thinner than twice the offset keeps a solid side: the surface moves at most to one cell
// short of its mid-plane.
TEST(VolumeMap, AThinPlateKeepsASolidSide) {
  const CubicSplineKernel kernel(4 * kR);
  const BoundaryObject plate = boxObject(Vector3r(0, 0, 0), Vector3r(Real(0.5), 2 * kR, Real(0.5)), false);
  const VolumeMap map(plate, kernel, Real(0.5) * kR, Real(1.35) * kR);
  // At most the 1 r half-thickness less one cell (the deepest grid node sets it: measured 0.35 r).
  EXPECT_GT(map.surfaceOffset(), 0);
  EXPECT_LE(map.surfaceOffset(), Real(0.5) * kR + Real(1e-6));
  EXPECT_LT(map.distance(Vector3r(Real(0.25), kR, Real(0.25))), 0);
  EXPECT_GT(map.distance(Vector3r(Real(0.25), 3 * kR, Real(0.25))), 0);
}

// An object's mapThickness moves its surface that far into the fluid (SPlisHSPlasH's Phi - t): on
// a floor, Phi is the height less t and V the half-space integral at that distance; a mesh
// body's distances all fall by t, wherever the unshifted map is exact, up to the trilinear
// interpolation of a sphere's distance (the thicker map's grid is t wider, so its nodes sit
// elsewhere: a cell^2 / (8 R) = 2.6e-4 m bound; measured 1.6e-5 m).
TEST(VolumeMap, ThicknessMovesTheSurfaceIntoTheFluid) {
  const CubicSplineKernel kernel(4 * kR);
  // One cell thick, so that the grid (grown by t) keeps its nodes at whole radii: V between
  // nodes is interpolated.
  BoundaryObject tank = boxObject(Vector3r::Zero(), Vector3r(1, 1, 1), true);
  tank.mapThickness = kR;
  const VolumeMap map(tank, kernel, kR);
  EXPECT_EQ(map.thickness(), kR);
  for (int k = 1; k < 5; ++k) {  // Phi = 0 .. 3 r, as on the plain floor above
    const Real t = kR;
    const Real y = Real(k) * kR;
    Real phi, volume;
    Vector3r phiGradient, volumeGradient;
    ASSERT_TRUE(map.sample(Vector3r(Real(0.5), y, Real(0.5)), phi, phiGradient, volume, volumeGradient));
    EXPECT_NEAR(phi, y - t, 1e-6);
    EXPECT_NEAR(volume / VolumeMap::halfSpaceVolume(kernel, y - t), 1, 2e-4) << "y = " << k << " r";
  }
  // The bundled sphere (0.3 m) as a body, with and without the thickness; with the offset too.
  TriangleMesh mesh = loadMesh(test::dataPath("meshes/sphere.obj"));
  transformMesh(mesh, Vector3r::Constant(Real(0.3)), Vector3r::UnitX(), 0, Vector3r::Zero());
  BoundaryObject ball;
  ball.name = ball.path = "ball";
  ball.mesh = mesh;
  const VolumeMap plain(ball, kernel, kR, Real(0.5) * kR);
  const Real t = Real(0.6) * kR;
  ball.mapThickness = t;
  const VolumeMap thick(ball, kernel, kR, Real(0.5) * kR);
  EXPECT_EQ(thick.surfaceOffset(), plain.surfaceOffset());
  int compared = 0;
  for (Real radius = Real(0.2); radius < Real(0.45); radius += Real(0.013)) {
    const Vector3r x = radius * Vector3r(1, 2, -2).normalized();
    if (plain.distance(x) > 4 * kR) continue;  // beyond the band the plain map is not exact
    EXPECT_NEAR(thick.distance(x), plain.distance(x) - t, kR * kR / (8 * Real(0.3))) << "|x| = " << radius;
    ++compared;
  }
  EXPECT_GE(compared, 10);
}

// Only the band is stored (bricks of nodes that reach it): inside a tank, every point within the
// band (2h + 3 cells) of a wall has its distance, while the middle of a tank wider than twice
// the band plus the bricks' slack holds no nodes; the same for a mesh body's far core. The
// bundled DamBreak tank at r = 0.0125 stores 8.0 M of its grid's 13.3 M nodes (measured).
TEST(VolumeMap, OnlyTheBandAroundTheSurfaceIsStored) {
  const CubicSplineKernel kernel(4 * kR);
  const Real band = 2 * 4 * kR + 3 * kR;
  const VolumeMap tank(boxObject(Vector3r::Zero(), Vector3r(2, 2, 2), true), kernel, kR);
  std::size_t dense = 1;
  for (int a = 0; a < 3; ++a) dense *= std::size_t(std::ceil((2 + 2 * (band + kR)) / kR)) + 1;
  EXPECT_LT(tank.nodeCount(), dense);  // 1.06 M of 1.16 M: a 2 m tank is mostly band
  for (Real y = Real(0.5) * kR; y < band - kR; y += Real(0.37) * kR)
    for (const Vector3r& x : {Vector3r(1, y, Real(1)), Vector3r(Real(0.3), Real(1.1), 2 - y), Vector3r(y, y, y)})
      EXPECT_LT(tank.distance(x), band) << x.transpose();  // stored, and the exact distance
  EXPECT_NEAR(tank.distance(Vector3r(1, 3 * kR, 1)), 3 * kR, 1e-6 * kR);
  EXPECT_EQ(tank.distance(Vector3r(1, 1, 1)), std::numeric_limits<Real>::max());  // the middle: not stored
  // A ball of radius 0.5 m (the bundled sphere mesh): the core holds nothing, the band does.
  TriangleMesh mesh = loadMesh(test::dataPath("meshes/sphere.obj"));
  BoundaryObject ball;
  ball.name = ball.path = "ball";
  ball.mesh = mesh;
  transformMesh(ball.mesh, Vector3r::Constant(Real(0.5)), Vector3r::UnitX(), 0, Vector3r::Zero());
  const VolumeMap body(ball, kernel, kR);
  EXPECT_EQ(body.distance(Vector3r::Zero()), std::numeric_limits<Real>::max());
  EXPECT_NEAR(body.distance(Vector3r(Real(0.5) - 3 * kR, 0, 0)), -3 * kR, Real(0.2) * kR);
  EXPECT_NEAR(body.distance(Vector3r(0, Real(0.5) + 5 * kR, 0)), 5 * kR, Real(0.2) * kR);
}

TEST(VolumeMap, AnOpenMeshIsAnErrorNamingTheObject) {
  const CubicSplineKernel kernel(4 * kR);
  BoundaryObject quad;
  quad.name = quad.path = "boundaries[0]";
  quad.mesh.vertices = {Vector3r(0, 0, 0), Vector3r(1, 0, 0), Vector3r(1, 0, 1), Vector3r(0, 0, 1)};
  quad.mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  try {
    VolumeMap map(quad, kernel, kR);
    FAIL() << "an open mesh must be refused";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("boundaries[0]: VolumeMap needs a closed mesh"), std::string::npos) << e.what();
  }
}

// A mesh (the bundled sphere, radius 0.5 m, 760 faces) as a container and as a body: Phi has the
// sign of the side and the size of the distance to the sphere, up to its faceting (~0.1 r).
TEST(VolumeMap, SphereMeshDistanceHasTheSideAsItsSign) {
  const Real r = Real(0.02);
  const CubicSplineKernel kernel(4 * r);
  TriangleMesh mesh = loadMesh(test::dataPath("meshes/sphere.obj"));
  transformMesh(mesh, Vector3r::Constant(Real(0.5)), Vector3r::UnitX(), 0, Vector3r::Zero());
  for (bool inverted : {true, false}) {
    BoundaryObject o;
    o.name = o.path = "sphere";
    o.mesh = mesh;
    o.inverted = inverted;
    const VolumeMap map(o, kernel, r);
    for (Real radius : {Real(0.44), Real(0.47), Real(0.53), Real(0.56)}) {
      const Vector3r x = radius * Vector3r(1, 2, -2).normalized();
      const Real fluidSide = inverted ? Real(0.5) - radius : radius - Real(0.5);
      EXPECT_NEAR(map.distance(x), fluidSide, 0.3 * r) << "inverted " << inverted << ", |x| = " << radius;
    }
  }
}

// The pairs' gradients are the gradient of the boundary density they give (Eq. 30 with an
// implicit boundary): sum_k m~_k grad_i against central differences of sum_k m~_k W(x_i - x_k).
// With one map per wall of the tank (the default) to round-off everywhere, at a wall, in an
// edge (two virtual particles) and in a corner (three): each wall's distance is a plane's. With
// one map for the whole tank ("containers": "whole") at a wall to round-off; in the edge and the
// corner, where the interpolated distance's gradient is shorter than 1 and the model takes the
// unit normal instead (VolumeMapBoundary_Bender2019.cpp), it points the same way and is larger
// (measured with r cells: 1.08 x in the edge, 1.53 x in the corner; 2r cells widen those cells:
// 1.94 x and 4.5 x).
class PairGradient : public ::testing::TestWithParam<const char*> {};

TEST_P(PairGradient, IsTheGradientOfTheBoundaryDensity) {
  const bool whole = std::string(GetParam()) == "whole";
  const CubicSplineKernel kernel(4 * kR);
  const LogSink quiet = [](LogLevel, const std::string&) {};
  FluidModel fluid("probe", 1000);
  const PluginContext context{&fluid, kR, kernel.supportRadius(), quiet, Real(1.8566) * kR};
  auto model = builtinPlugins().boundaryModels.create(
      "VolumeMap", json{{"type", "VolumeMap"}, {"offsetObjects", "none"}, {"cellSize", 1.0}, {"containers", GetParam()}},
      "simulation.boundaryModel", context, quiet);
  model->initialize({boxObject(Vector3r::Zero(), Vector3r(1, 1, 1), true)}, fluid, kernel);
  // The central difference's step. In float a step of 1e-5 m leaves the densities' round-off
  // (eps rho over the step) and x +- eps's rounding at ulp(0.5) = 6e-8 m at 1e-3 of the gradient
  // (measured ratio 1.0013 against the bound 1.001), so it is the round-off/truncation optimum,
  // cbrt(eps) times the lattice spacing 2r: 2.5e-4 m, round-off ~ eps h / step = 5e-5,
  // truncation ~ (step / r)^2 / 6 = 2e-5 of the gradient (measured 0.9999).
  const Real eps = Real(test::roundoff(1e-5, std::cbrt(test::kFloatEps) * 2 * kR));
  struct Probe {
    Vector3r x;
    Real minRatio, maxRatio;  // |gradient| / |difference|
  };
  struct Place {
    Probe probe;
    Index virtualParticles;  // with one map per wall
  };
  for (const Place& place : {Place{Probe{Vector3r(0.5, 2.7 * kR, 0.5), Real(0.999), Real(1.001)}, 1},
                             Place{Probe{Vector3r(0.5, 2.2 * kR, 2.9 * kR), Real(1), Real(1.2)}, 2},
                             Place{Probe{Vector3r(2.6 * kR, 2.4 * kR, 2.8 * kR), Real(1), Real(1.7)}, 3}}) {
    const Probe probe = whole ? place.probe : Probe{place.probe.x, Real(0.999), Real(1.001)};
    const Vector3r x = probe.x;
    fluid.resize(7);
    fluid.positions[0] = x;
    for (int a = 0; a < 3; ++a) {
      fluid.positions[1 + 2 * a] = x + eps * Vector3r::Unit(a);
      fluid.positions[2 + 2 * a] = x - eps * Vector3r::Unit(a);
    }
    NeighborLists lists;
    model->findNeighbors(fluid, kernel, lists, nullptr);
    const BoundarySamples& b = model->samples();
    auto density = [&](std::size_t i) {
      Real rho = 0;
      for (Index e = lists.begin(i); e < lists.end(i); ++e) rho += b.masses[lists.indices[e]] * kernel.W(fluid.positions[i] - b.positions[lists.indices[e]]);
      return rho;
    };
    Vector3r gradient = Vector3r::Zero(), difference;
    for (Index e = lists.begin(0); e < lists.end(0); ++e) gradient += b.masses[lists.indices[e]] * lists.gradW[e];
    // Divided by the step between the positions as stored (x +- eps is rounded to x's ulp).
    for (int a = 0; a < 3; ++a)
      difference[a] = (density(1 + 2 * a) - density(2 + 2 * a)) / (fluid.positions[1 + 2 * a][a] - fluid.positions[2 + 2 * a][a]);
    ASSERT_EQ(lists.count(0), whole ? 1u : place.virtualParticles);
    EXPECT_GT(density(0), 0);
    const Real ratio = gradient.norm() / difference.norm(), cosine = gradient.normalized().dot(difference.normalized());
    std::printf("%s: at (%.1f, %.1f, %.1f) r: |gradient| / |difference| = %.4f, cosine %.6f\n", GetParam(), double(x[0] / kR),
                double(x[1] / kR), double(x[2] / kR), double(ratio), double(cosine));
    EXPECT_GE(ratio, probe.minRatio);
    EXPECT_LE(ratio, probe.maxRatio);
    EXPECT_GT(cosine, 0.999);
  }
}

INSTANTIATE_TEST_SUITE_P(Containers, PairGradient, ::testing::Values("walls", "whole"),
                         [](const auto& info) { return std::string(info.param); });

// A moving body's map goes with it: a plate 0.4 x 0.1 x 0.4 m turned by 90 degrees about z
// through its centre. A fluid particle 2.5 r off the turned plate's thin face (x = 0.25) gets one
// virtual particle 3 r behind it along +x, moving with the body's velocity at the fluid
// particle; one above where the plate's top face was (and no longer is) gets none.
TEST(VolumeMapBoundary, AMovingBodysMapTurnsWithIt) {
  const CubicSplineKernel kernel(4 * kR);
  const LogSink quiet = [](LogLevel, const std::string&) {};
  FluidModel fluid("probe", 1000);
  const PluginContext context{&fluid, kR, kernel.supportRadius(), quiet, Real(1.8566) * kR};
  auto model = builtinPlugins().boundaryModels.create("VolumeMap", json{{"type", "VolumeMap"}, {"offsetObjects", "none"}},
                                                      "simulation.boundaryModel", context, quiet);
  BoundaryObject plate = boxObject(Vector3r::Zero(), Vector3r(0.4, 0.1, 0.4), false);
  plate.motion = BodyMotion::Dynamic;
  model->initialize({plate}, fluid, kernel);
  ObjectPose pose;
  pose.initialCentre = pose.centre = Vector3r(0.2, 0.05, 0.2);
  pose.rotation = Eigen::AngleAxis<Real>(Real(std::numbers::pi / 2), Vector3r::UnitZ()).toRotationMatrix();
  pose.velocity = Vector3r(0.1, 0, 0);
  pose.angularVelocity = Vector3r(0, 0, 2);
  model->follow({PoseUpdate{0, pose}});
  fluid.resize(2);
  fluid.positions[0] = Vector3r(0.25 + 2.5 * kR, 0.05, 0.2);  // beside the turned plate
  fluid.positions[1] = Vector3r(0.4, 0.1 + 2.5 * kR, 0.2);    // above where its top face was, 6 r off the turned plate
  NeighborLists lists;
  model->findNeighbors(fluid, kernel, lists, nullptr);
  ASSERT_EQ(lists.count(0), 1u);
  EXPECT_EQ(lists.count(1), 0u);
  const BoundarySamples& b = model->samples();
  const Index k = lists.indices[lists.begin(0)];
  const Vector3r expected = fluid.positions[0] - 3 * kR * Vector3r::UnitX();  // s = Phi + r/2
  EXPECT_LT((b.positions[k] - expected).norm(), Real(1e-3) * kR) << b.positions[k].transpose();
  const Vector3r v = pose.velocity + pose.angularVelocity.cross(fluid.positions[0] - pose.centre);
  EXPECT_LT((b.velocities[k] - v).norm(), Real(1e-12)) << b.velocities[k].transpose();
  EXPECT_GT(std::abs(lists.gradW[lists.begin(0)].normalized().dot(Vector3r::UnitX())), Real(0.999));
  // The mass is the unturned plate's volume at the same distance from a face.
  fluid.positions[0] = Vector3r(0.2, -2.5 * kR, 0.2);
  model->follow({PoseUpdate{0, ObjectPose{Matrix3r::Identity(), pose.centre, pose.initialCentre}}});
  NeighborLists unturned;
  const Real mass = b.masses[k];
  model->findNeighbors(fluid, kernel, unturned, nullptr);
  ASSERT_EQ(unturned.count(0), 1u);
  EXPECT_NEAR(model->samples().masses[unturned.indices[unturned.begin(0)]], mass, Real(1e-9) * mass);
}

// Mirroring and extrapolation push with p_k = p_i from the one virtual particle: the log says so.
TEST(VolumeMapBoundary, MirroringAndExtrapolationWarnThatTheyArePkEqualsPi) {
  for (const char* treatment : {"mirroring", "extrapolation"}) {
    json s = {{"simulation", {{"particleRadius", 0.025}, {"boundaryModel", "VolumeMap"}, {"boundaryPressure", treatment}}},
              {"fluids", {{{"blocks", {{{"min", {0.1, 0.1, 0.1}}, {"max", {0.3, 0.3, 0.3}}}}}}}},
              {"boundaries", {{{"box", {{"min", {0, 0, 0}}, {"max", {1, 1, 1}}}}, {"inverted", true}}}}};
    test::CapturedLog log;
    test::simulationFromJson(s, log.sink());
    ASSERT_EQ(log.warnings.size(), 1u) << treatment;
    EXPECT_NE(log.warnings[0].find("p_k = p_i"), std::string::npos) << log.warnings[0];
    EXPECT_NE(log.warnings[0].find(treatment), std::string::npos) << log.warnings[0];
  }
}

// A container gets one map per wall when it is an axis-aligned box, given as a "box" or as a mesh
// (SPlisHSPlasH scenes give their tanks as UnitBox.obj, inverted, scaled and moved): the same
// six slabs, so the same virtual particles. A turned box or a sphere keeps one map.
TEST(VolumeMapBoundary, AnInvertedBoxMeshIsSplitIntoWallsLikeABox) {
  auto mapsFor = [](const json& tank) {
    json scene = {{"simulation", {{"particleRadius", 0.025}, {"boundaryModel", {{"type", "VolumeMap"}, {"cache", ""}}}}},
                  {"fluids", {{{"blocks", {{{"min", {0.1, 0.1, 0.1}}, {"max", {0.3, 0.3, 0.3}}}}}}}},
                  {"boundaries", {tank}}};
    auto sim = test::simulationFromJson(scene);
    const auto& model = dynamic_cast<const VolumeMapBoundary_Bender2019&>(sim->boundaryModel());
    sim->step();
    return std::make_pair(model.mapCount(), sim->fluid().positions);
  };
  const json box = {{"box", {{"min", {0, 0, 0}}, {"max", {0.4, 0.6, 0.4}}}}, {"inverted", true}};
  const json mesh = {{"mesh", "../meshes/UnitBox.obj"}, {"scale", {0.4, 0.6, 0.4}}, {"translation", {0.2, 0.3, 0.2}}, {"inverted", true}};
  const auto [boxMaps, boxPositions] = mapsFor(box);
  const auto [meshMaps, meshPositions] = mapsFor(mesh);
  EXPECT_EQ(boxMaps, 6u);
  EXPECT_EQ(meshMaps, 6u);
  ASSERT_EQ(boxPositions.size(), meshPositions.size());
  for (std::size_t i = 0; i < boxPositions.size(); ++i)
    EXPECT_LT((boxPositions[i] - meshPositions[i]).norm(), Real(1e-5)) << "particle " << i;
  json turned = mesh;
  turned["rotationAxis"] = {0, 1, 0};
  turned["rotationAngle"] = 0.3;
  EXPECT_EQ(mapsFor(turned).first, 1u);
  json sphere = {{"mesh", "../meshes/sphere.obj"}, {"scale", {0.5, 0.5, 0.5}}, {"translation", {0.2, 0.2, 0.2}}, {"inverted", true}};
  EXPECT_EQ(mapsFor(sphere).first, 1u);
}

// Moving bodies take their map along; rigid contact samples their surfaces for itself (they
// have no sample layers), so nothing needs a warning.
// Per-object map settings: an object's mapCellSize (radii) replaces the model's cellSize for its
// map alone, its mapThickness reaches its map; Akinci samples warn that they ignore both.
TEST(VolumeMapBoundary, ObjectsChooseTheirOwnCellSizeAndThickness) {
  json scene = json::parse(R"({
    "simulation": {"particleRadius": 0.025, "boundaryModel": {"type": "VolumeMap", "cache": ""}},
    "fluids": [{"blocks": [{"min": [0.05, 0.05, 0.05], "max": [0.3, 0.2, 0.3]}]}],
    "boundaries": [{"box": {"min": [0, 0, 0], "max": [1, 1, 1]}, "inverted": true, "mapCellSize": 2},
                   {"name": "ball", "mesh": "../meshes/sphere.obj", "scale": [0.15, 0.15, 0.15], "translation": [0.6, 0.5, 0.5],
                    "mapCellSize": 0.5, "mapThickness": 0.01}]
  })");
  test::CapturedLog log;
  auto sim = test::simulationFromJson(scene, log.sink());
  const auto& model = dynamic_cast<const VolumeMapBoundary_Bender2019&>(sim->boundaryModel());
  EXPECT_EQ(model.map(0).cellSize(), 2 * kR);
  EXPECT_EQ(model.map(1).cellSize(), Real(0.5) * kR);
  EXPECT_EQ(model.map(0).thickness(), 0);
  EXPECT_EQ(model.map(1).thickness(), Real(0.01));
  EXPECT_TRUE(log.warnings.empty()) << log.warnings[0];

  scene["simulation"]["boundaryModel"] = "Akinci2012";
  test::CapturedLog akinciLog;
  test::simulationFromJson(scene, akinciLog.sink());
  int warned = 0;
  for (const std::string& w : akinciLog.warnings)
    warned += w.find("mapCellSize and mapThickness are volume-map settings") != std::string::npos;
  EXPECT_EQ(warned, 2) << "one warning per object that sets them";
  // Below a quarter radius (but not 0, the model's) is refused with the key's path.
  scene["boundaries"][1]["mapCellSize"] = 0.1;
  try {
    test::simulationFromJson(scene);
    FAIL() << "mapCellSize 0.1 must be refused";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("boundaries[1].mapCellSize"), std::string::npos) << e.what();
  }
}

TEST(VolumeMapBoundary, DynamicBodiesGetContactPointsWithoutAWarning) {
  json s = {{"simulation", {{"particleRadius", 0.025}, {"boundaryModel", "VolumeMap"}}},
            {"fluids", {{{"blocks", {{{"min", {0.1, 0.1, 0.1}}, {"max", {0.3, 0.3, 0.3}}}}}}}},
            {"boundaries", {{{"box", {{"min", {0, 0, 0}}, {"max", {1, 1, 1}}}}, {"inverted", true}},
                            {{"box", {{"min", {0.5, 0.5, 0.5}}, {"max", {0.6, 0.6, 0.6}}}}, {"dynamic", true}, {"density", 500}}}}};
  test::CapturedLog log;
  auto sim = test::simulationFromJson(s, log.sink());
  EXPECT_TRUE(log.warnings.empty()) << log.warnings[0];
  // Its 0.1 m cube, r/2 inside: a 0.075 m cube's faces sampled r apart (measured: 98 points).
  const RigidBody& body = test::rigidBodies(*sim)->bodies().at(0);
  EXPECT_GT(body.contactSamples.size(), 80u);
  EXPECT_TRUE(body.samples.empty());
  // The body falls in the empty upper tank as it would with sample layers.
  sim->run(Real(0.1));
  EXPECT_NEAR(test::rigidBodies(*sim)->bodies().at(0).v[1], -9.81 * 0.1, 0.02);
}


// The surface a particle near a tank's floor edge meets is two walls: its normal moments split
// into the side wall's (n n^T = x x^T only) and the floor's (y y^T only), which add up to the
// whole; the load a force probe's region takes is split by them (VolumeMapBoundary_Bender2019::
// impulseInBox).
TEST(VolumeMap, NormalMomentsSplitAnEdgeIntoItsWalls) {
  const CubicSplineKernel kernel(4 * kR);
  const VolumeMap map(boxObject(Vector3r::Zero(), Vector3r(1, 1, 1), true), kernel, kR);
  const Vector3r x(Real(1.5) * kR, Real(1.2) * kR, Real(0.5));
  Matrix3r whole, side, floor, unused;
  // A side-wall foot has x = 0 < y, a floor foot y = 0 < x.
  map.normalMoments(x, kernel, [](const Vector3r& foot) { return foot[0] < foot[1]; }, whole, side);
  map.normalMoments(x, kernel, [](const Vector3r& foot) { return !(foot[0] < foot[1]); }, unused, floor);
  EXPECT_GT(side(0, 0), 0);
  EXPECT_GT(floor(1, 1), 0);
  EXPECT_LT((side - side(0, 0) * Vector3r::UnitX() * Vector3r::UnitX().transpose()).norm(), 1e-12 * whole.norm());
  EXPECT_LT((floor - floor(1, 1) * Vector3r::UnitY() * Vector3r::UnitY().transpose()).norm(), 1e-12 * whole.norm());
  EXPECT_LT((side + floor - whole).norm(), 1e-12 * whole.norm());
  // The particle is nearer the floor: the floor's share is the larger.
  EXPECT_GT(floor(1, 1), side(0, 0));
}
