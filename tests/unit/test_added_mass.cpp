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

// One particle touching (the first under a body reaching the surface; a row of three under a
// falling 400 kg/m^3 box was thrown at 49.5 m/s in the stress suite's 50 boxes when its singular
// rigid mass matrix was solved). The body's increment is the same as for any cloud; the particle
// moves with the body by the added share (here all of it), no faster than the body's own
// increment at its point plus the uniform part that keeps momentum exact.
TEST(AddedMass, OneTouchingParticleMovesWithTheBodyAndMomentumStaysExact) {
  const RigidBody b = spinningBody();
  const Vector3r r(0.002, -0.07, -0.044);
  std::vector<Vector3r> x{b.x + r}, v{Vector3r(0.01, 0, 0)};
  std::vector<Real> m{Real(3.4e-3)};
  const std::vector<Vector3r> v0 = v;
  const Vector3r N(0.01, -0.06, 0.02), L(3e-4, -1e-4, 2e-4);
  const Real dt = 0.003, addedMass = 1;  // more than the particle: all of it moves with the body
  const BodyIncrement inc = shareWithTouchingFluid(b, N, L, dt, addedMass, {0}, x, m, v);
  const Matrix3r R = b.rotation(), I = R * b.inertiaBody * R.transpose();
  const Matrix3r Ic = m[0] * (r.squaredNorm() * Matrix3r::Identity() - r * r.transpose());
  const Vector3r angular = L - dt * b.w.cross(I * b.w);
  EXPECT_NEAR((inc.dv - N / (b.mass + m[0])).norm(), 0, roundoff(1e-14, 1e-5) * inc.dv.norm());
  EXPECT_NEAR((inc.dw - (I + Ic).inverse() * angular).norm(), 0, roundoff(1e-12, 1e-4) * inc.dw.norm());
  const Vector3r P = b.mass * inc.dv + m[0] * (v[0] - v0[0]);
  EXPECT_NEAR((P - N).norm() / N.norm(), 0, roundoff(1e-12, 200 * kFloatEps));
  // dv + dw x r, minus dw x r for momentum: the particle takes the body's translation.
  EXPECT_NEAR((v[0] - v0[0] - inc.dv).norm(), 0, roundoff(1e-12, 1e-4) * inc.dv.norm());
}
