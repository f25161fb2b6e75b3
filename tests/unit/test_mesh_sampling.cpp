// Surface sampling with the sample layer moved off the mesh: the moved layer must stay closed
// (no strip open along a container's edges for fluid to leak through) and at the offset.
#include <gtest/gtest.h>

#include <cmath>

#include "Boundary/MeshSampling.h"
#include "Boundary/ParticleBoundary_Akinci2012.h"
#include "Simulation/NeighborSearch.h"
#include "Utilities/TriangleMesh.h"
#include "TestUtil.h"

using namespace consph;

namespace {

// Distance from p to the surface of the box [lo, hi] (p outside or inside).
Real boxSurfaceDistance(const Vector3r& p, const Vector3r& lo, const Vector3r& hi) {
  const Vector3r outside = (lo - p).cwiseMax(p - hi).cwiseMax(Vector3r::Zero());
  if (outside.norm() > 0) return outside.norm();
  return std::min((p - lo).minCoeff(), (hi - p).minCoeff());
}

}  // namespace

TEST(MeshSampling, OffsetContainerLayerIsClosedAndAtTheOffset) {
  const Vector3r lo(0, 0, 0), hi(Real(0.6), Real(0.4), Real(0.5));
  const Real spacing = Real(0.02), offset = Real(0.025);
  const TriangleMesh container = makeBoxMesh(lo, hi, true);  // triangles face into the box
  // Into the solid = against the winding normals of a container.
  const std::vector<Vector3r> samples = sampleMeshSurface(container, spacing, -offset);
  PointGrid grid;
  grid.build(samples.data(), samples.size(), spacing);
  // Every sample lies `offset` outside the mesh, in the solid (up to the arcs' chords).
  for (const Vector3r& x : samples) {
    ASSERT_TRUE((x - lo).minCoeff() < 0 || (hi - x).minCoeff() < 0) << x.transpose();
    ASSERT_NEAR(boxSurfaceDistance(x, lo, hi), offset, 0.02 * offset) << x.transpose();
  }
  // Every point of the moved surface (the box grown by the offset with rounded edges and
  // corners) has a sample within one spacing: edges and corners included.
  const Vector3r glo = lo - Vector3r::Constant(offset), ghi = hi + Vector3r::Constant(offset);
  int probes = 0;
  for (int i = 0; i <= 60; ++i)
    for (int j = 0; j <= 40; ++j)
      for (int k = 0; k <= 50; ++k) {
        const Vector3r p = glo + (ghi - glo).cwiseProduct(Vector3r(i / 60.0, j / 40.0, k / 50.0));
        const Vector3r inner = p.cwiseMax(lo).cwiseMin(hi);  // closest point of the box
        if ((p - glo).minCoeff() > 1e-9 && (ghi - p).minCoeff() > 1e-9) continue;  // not on the grown box
        const Vector3r onLayer = inner + offset * (p - inner).normalized();
        Real nearest = 1e9;
        grid.forEachNeighbor(onLayer, spacing, [&](Index, const Vector3r& x) { nearest = std::min(nearest, (x - onLayer).norm()); });
        ASSERT_LT(nearest, spacing) << "hole in the sample layer at " << onLayer.transpose();
        ++probes;
      }
  EXPECT_GT(probes, 1000);
}

TEST(MeshSampling, BodyLayerMovesInwards) {
  const Vector3r lo(0, 0, 0), hi(Real(0.3), Real(0.3), Real(0.3));
  const TriangleMesh body = makeBoxMesh(lo, hi, false);
  for (const Vector3r& x : sampleMeshSurface(body, Real(0.02), Real(-0.03))) {
    ASSERT_GT((x - lo).minCoeff(), Real(0.03) - Real(1e-9));
    ASSERT_GT((hi - x).minCoeff(), Real(0.03) - Real(1e-9));
  }
}

// The fluid's first layer rests about one lattice spacing from a flat sample layer; the
// computed distance must give rest density there and lie in the range the measurements show
// (a resting column: 1.8-2.2 r from the samples).
TEST(MeshSampling, RestDistanceFromAWallIsAboutOneLatticeSpacing) {
  const Real r = Real(0.01);
  const CubicSplineKernel kernel(4 * r);
  const Real D = ParticleBoundary_Akinci2012::restDistance(kernel, r, Real(1.8566) * r);
  EXPECT_GT(D, Real(1.6) * r);
  EXPECT_LT(D, Real(2.4) * r);
  // Scale-free: the same in units of r at another radius.
  const Real r2 = Real(0.05);
  // Float: the distance is the root of a density balance whose sums have 9 x 13^2 = 1521 kernel
  // terms each, rounded differently at the two radii: ~sqrt(1521) = 39 eps relative (measured 5.6 eps).
  EXPECT_NEAR(ParticleBoundary_Akinci2012::restDistance(CubicSplineKernel(4 * r2), r2, Real(1.8566) * r2) / r2, D / r,
              test::roundoff(1e-6, 40 * test::kFloatEps * D / r));
}
