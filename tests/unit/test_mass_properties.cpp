// Mass properties by the divergence theorem against closed-form values, winding numbers, and
// the particle-field budget (reserve / compact) emitters rely on.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "Simulation/ParticleFields.h"
#include "Utilities/MassProperties.h"
#include "TestUtil.h"

using namespace consph;
using consph::test::kFloatEps;
using consph::test::roundoff;

TEST(MassProperties, BoxMatchesClosedForm) {
  // A box a x b x c far from the origin: V = abc, centre, I_xx = V (b^2 + c^2) / 12, no products.
  const Vector3r lo(10, -20, 30), hi(10.4, -19.7, 30.2);
  const MassProperties m = computeMassProperties(makeBoxMesh(lo, hi, false));
  const Real a = 0.4, b = 0.3, c = 0.2, V = a * b * c;
  // Float: the integration runs in double, but the vertices are floats: at |x| = 10, 20, 30 each
  // is rounded by up to eps |x| / 2, so the sides a, b, c are off by up to eps |x| relative to
  // them, and V by the sum of those (242 eps; measured 2 eps), the inertia by up to 3 times that.
  const double sides = kFloatEps * (10 / a + 20 / b + 30 / c);
  EXPECT_NEAR(m.volume, V, roundoff(1e-12, sides * V));
  EXPECT_NEAR((m.centerOfMass - (lo + hi) / 2).norm(), 0, 1e-11);
  EXPECT_NEAR(m.inertiaPerDensity(0, 0), V * (b * b + c * c) / 12, roundoff(1e-12, 3 * sides * V * (b * b + c * c) / 12));
  EXPECT_NEAR(m.inertiaPerDensity(1, 1), V * (a * a + c * c) / 12, roundoff(1e-12, 3 * sides * V * (a * a + c * c) / 12));
  EXPECT_NEAR(m.inertiaPerDensity(2, 2), V * (a * a + b * b) / 12, roundoff(1e-12, 3 * sides * V * (a * a + b * b) / 12));
  EXPECT_NEAR(m.inertiaPerDensity(0, 1), 0, 1e-12);
  EXPECT_NEAR(m.inertiaPerDensity(1, 2), 0, 1e-12);
  EXPECT_NEAR(m.inertiaPerDensity(0, 2), 0, 1e-12);
  // Inward-facing triangles give a negative volume (how a container is told apart).
  EXPECT_NEAR(computeMassProperties(makeBoxMesh(lo, hi, true)).volume, -V, roundoff(1e-12, sides * V));
}

TEST(MassProperties, RotatedBoxInertiaIsRotated) {
  TriangleMesh mesh = makeBoxMesh(Vector3r(-0.5, -0.1, -0.2), Vector3r(0.5, 0.1, 0.2), false);
  const Vector3r axis = Vector3r(1, 2, 3).normalized();
  const Real angle = 0.7;
  const MassProperties m0 = computeMassProperties(mesh);
  transformMesh(mesh, Vector3r::Ones(), axis, angle, Vector3r(1, 2, 3));
  const MassProperties m = computeMassProperties(mesh);
  const Matrix3r R = Eigen::AngleAxis<Real>(angle, axis).toRotationMatrix();
  EXPECT_NEAR((m.centerOfMass - Vector3r(1, 2, 3)).norm(), 0, 1e-12);
  // Float: transformMesh rounds the turned vertices (|x| <= |(1, 2, 3)| + 0.55) by eps |x|, which
  // is 43 eps of the box's smallest half-side 0.1; the inertia, quadratic in the extents, moves
  // by twice that relative (measured 4 eps).
  const double shape = kFloatEps * (Vector3r(1, 2, 3).norm() + 0.55) / 0.1;
  EXPECT_NEAR((m.inertiaPerDensity - R * m0.inertiaPerDensity * R.transpose()).norm(), 0,
              roundoff(1e-12, 2 * shape * m0.inertiaPerDensity.norm()));
}

TEST(MassProperties, WindingNumberInsideOutside) {
  const TriangleMesh mesh = makeBoxMesh(Vector3r(0, 0, 0), Vector3r(1, 1, 1), false);
  EXPECT_NEAR(windingNumber(mesh, Vector3r(0.5, 0.3, 0.9)), 1, 1e-9);
  EXPECT_NEAR(windingNumber(mesh, Vector3r(1.5, 0.3, 0.9)), 0, 1e-9);
  EXPECT_NEAR(windingNumber(mesh, Vector3r(-3, 7, 2)), 0, 1e-9);
}

TEST(ParticleFields, ReserveKeepsPointersAndCompactDropsParticles) {
  ParticleFields f;
  auto& x = f.add<Real>("x", FieldSorted, 0);
  f.reserve(100);
  auto& y = f.add<Index>("y", FieldNone, 0);  // added after reserve: reserved too
  const Real* px = x.data();
  const Index* py = y.data();
  f.resize(10);
  for (Index i = 0; i < 10; ++i) x[i] = Real(i), y[i] = i;
  f.resize(100);
  EXPECT_EQ(px, x.data());
  EXPECT_EQ(py, y.data());
  EXPECT_THROW(f.resize(101), SimulationError);
  f.resize(10);
  f.compact({1, 4, 9});
  ASSERT_EQ(f.size(), 3u);
  EXPECT_EQ(x[0], 1);
  EXPECT_EQ(x[2], 9);
  EXPECT_EQ(y[1], 4u);
  EXPECT_EQ(px, x.data());
}
