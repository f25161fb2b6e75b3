// Utilities/MeshClosure.h: closed, open, non-manifold and inconsistently oriented meshes.
#include <gtest/gtest.h>

#include "TestUtil.h"
#include "Utilities/MeshClosure.h"

using namespace consph;

TEST(MeshClosure, BoxesAndTheBundledBodyMeshesAreClosed) {
  EXPECT_TRUE(checkClosure(makeBoxMesh(Vector3r::Zero(), Vector3r::Ones(), false)).closed());
  EXPECT_TRUE(checkClosure(makeBoxMesh(Vector3r::Zero(), Vector3r::Ones(), true)).closed());
  for (const char* mesh : {"meshes/UnitBox.obj", "meshes/sphere.obj", "meshes/WaterWheel.obj"})
    EXPECT_TRUE(checkClosure(loadMesh(test::dataPath(mesh))).closed()) << mesh << ": " << checkClosure(loadMesh(test::dataPath(mesh))).describe();
}

TEST(MeshClosure, AMissingFaceAFlippedTriangleAndAFinAreFound) {
  TriangleMesh box = makeBoxMesh(Vector3r::Zero(), Vector3r::Ones(), false);
  TriangleMesh open = box;
  open.triangles.pop_back();  // half a face gone: its three edges are open
  EXPECT_EQ(checkClosure(open).openEdges, 3u);
  EXPECT_EQ(checkClosure(open).describe(), "3 open edges");
  TriangleMesh flipped = box;
  std::swap(flipped.triangles[0][1], flipped.triangles[0][2]);
  EXPECT_EQ(checkClosure(flipped).flippedEdges, 3u);
  TriangleMesh fin = box;
  fin.vertices.push_back(Vector3r(2, 2, 2));
  const auto& t = box.triangles[0];
  fin.triangles.push_back({t[0], t[1], Index(fin.vertices.size() - 1)});
  fin.triangles.push_back({t[1], t[0], Index(fin.vertices.size() - 1)});
  EXPECT_EQ(checkClosure(fin).nonManifoldEdges, 1u);
  // Vertices repeated per face are welded by position.
  TriangleMesh split;
  for (const auto& tri : box.triangles) {
    const Index base = Index(split.vertices.size());
    for (int c = 0; c < 3; ++c) split.vertices.push_back(box.vertices[tri[c]]);
    split.triangles.push_back({base, base + 1, base + 2});
  }
  EXPECT_TRUE(checkClosure(split).closed());
}
