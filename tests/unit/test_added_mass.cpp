// A light body's impulse shared with the fluid it touches (Boundary/AddedMass.h): the body's
// increment is N / (m + m_a), and body plus fluid gain exactly the impulses, linear and angular.
#include <gtest/gtest.h>

#include "Boundary/AddedMass.h"
#include "TestUtil.h"

using namespace consph;
using consph::test::kFloatEps;
using consph::test::roundoff;

namespace {
RigidBody spinningBody() {
  RigidBody b;
  b.mass = 0.01;
  b.volume = 0.001;
  b.inertiaBody = Matrix3r(Vector3r(2e-5, 3e-5, 4e-5).asDiagonal());
  b.invInertiaBody = b.inertiaBody.inverse();
  b.x = Vector3r(0.2, 0.1, -0.3);
  b.q = Quaternionr(Eigen::AngleAxis<Real>(Real(0.4), Vector3r(1, 2, 3).normalized()));
  b.v = Vector3r(0.1, -0.2, 0.3);
  b.w = Vector3r(1, -2, 0.5);
  return b;
}
}  // namespace

TEST(AddedMass, BodyAndTouchingFluidGainExactlyTheImpulses) {
  const RigidBody b = spinningBody();
  std::vector<Vector3r> x, v;
  std::vector<Real> m;
  std::vector<Index> touching;
  for (int i = 0; i < 12; ++i) {  // an uneven cloud about the body (first moment not zero)
    x.push_back(b.x + Vector3r(0.05 * std::cos(i), 0.04 * std::sin(2 * i) + 0.01, 0.03 * (i % 3 - 1)));
    v.push_back(Vector3r(0.01 * i, 0, -0.02));
    m.push_back(Real(0.1 + 0.01 * i));
    if (i % 4 != 3) touching.push_back(Index(i));  // not every particle touches
  }
  const std::vector<Vector3r> v0 = v;
  const Vector3r N(0.3, 1.2, -0.4), L(2e-3, -1e-3, 4e-4);
  const Real dt = 0.005, addedMass = 0.4;
  const BodyIncrement inc = shareWithTouchingFluid(b, N, L, dt, addedMass, touching, x, m, v);
  EXPECT_NEAR((inc.dv - N / (b.mass + addedMass)).norm(), 0, roundoff(1e-14, 8 * kFloatEps * N.norm() / addedMass));
  const Matrix3r R = b.rotation(), I = R * b.inertiaBody * R.transpose();
  Vector3r P = b.mass * inc.dv, A = I * inc.dw;
  for (std::size_t i = 0; i < x.size(); ++i) {
    P += m[i] * (v[i] - v0[i]);
    A += m[i] * (x[i] - b.x).cross(v[i] - v0[i]);
  }
  // The gyroscopic term is the body's own (applyImpulses): not an exchange with the fluid.
  const Vector3r angular = L - dt * b.w.cross(I * b.w);
  EXPECT_NEAR((P - N).norm() / N.norm(), 0, roundoff(1e-12, 200 * kFloatEps));
  EXPECT_NEAR((A - angular).norm() / angular.norm(), 0, roundoff(1e-10, 2e4 * kFloatEps));
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (i % 4 == 3) {
      EXPECT_EQ(v[i], v0[i]);  // only the touching particles are moved
    }
  }
}

TEST(AddedMass, WithoutTouchingFluidTheBodyTakesItAlone) {
  RigidBody b = spinningBody();
  std::vector<Vector3r> x, v;
  std::vector<Real> m;
  const Vector3r N(0.3, 1.2, -0.4), L(2e-3, -1e-3, 4e-4);
  const Real dt = 0.005;
  const BodyIncrement inc = shareWithTouchingFluid(b, N, L, dt, Real(0.4), {}, x, m, v);
  const Vector3r v0 = b.v, w0 = b.w;
  b.applyImpulses(N, L, dt);
  EXPECT_NEAR((inc.dv - (b.v - v0)).norm(), 0, roundoff(1e-12, 1e-4));
  EXPECT_NEAR((inc.dw - (b.w - w0)).norm(), 0, roundoff(1e-10, 1e-2));
}
