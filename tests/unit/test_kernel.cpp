// Cubic spline kernel: normalisation, symmetry and gradient properties.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "Simulation/Kernel.h"
#include "TestUtil.h"

using namespace consph;

namespace {
// Integrates f over the support with a midpoint rule on a fine grid.
template <class F>
double integrateOverSupport(Real h, int n, F f) {
  const double d = 2.0 * h / n;
  double sum = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        const Vector3r x(Real(-h + (i + 0.5) * d), Real(-h + (j + 0.5) * d), Real(-h + (k + 0.5) * d));
        sum += f(x);
      }
  return sum * d * d * d;
}
}  // namespace

TEST(CubicSplineKernel, IntegratesToOne) {
  const CubicSplineKernel kernel(Real(0.1));
  const double integral = integrateOverSupport(Real(0.1), 80, [&](const Vector3r& x) { return double(kernel.W(x)); });
  EXPECT_NEAR(integral, 1.0, 2e-3);
}

TEST(CubicSplineKernel, CompactSupportAndPositive) {
  const CubicSplineKernel kernel(Real(0.2));
  EXPECT_EQ(kernel.W(Real(0.2)), 0);
  EXPECT_EQ(kernel.W(Real(0.25)), 0);
  EXPECT_EQ(kernel.gradW(Vector3r(Real(0.21), 0, 0)).norm(), 0);
  for (Real r = 0; r < Real(0.2); r += Real(0.01)) EXPECT_GT(kernel.W(r), 0);
  // Float: W0 = 8 / (pi h^3) takes 4 roundings in Real (measured 1.1 eps).
  EXPECT_NEAR(kernel.W0(), 8 / (std::numbers::pi * 0.008), test::roundoff(1e-9, 4 * test::kFloatEps) * kernel.W0());
}

TEST(CubicSplineKernel, GradientIsAntisymmetricAndPointsInwards) {
  const CubicSplineKernel kernel(Real(0.1));
  for (const Vector3r& x : {Vector3r(Real(0.01), Real(0.02), Real(-0.03)), Vector3r(Real(0.06), 0, Real(0.04))}) {
    const Vector3r g = kernel.gradW(x);
    // Float: |-x| and |x| may round an ulp apart (measured 3.4e-8 relative).
    EXPECT_LT((g + kernel.gradW(-x)).norm(), test::roundoff(1e-12, 4 * test::kFloatEps) * (1 + g.norm()));
    EXPECT_LT(g.dot(x), 0);  // W decreases outwards
    EXPECT_NEAR(g.normalized().dot(x.normalized()), -1, 1e-6);
  }
  EXPECT_EQ(kernel.gradW(Vector3r::Zero()).norm(), 0);
}

TEST(CubicSplineKernel, GradientMatchesFiniteDifferences) {
  const CubicSplineKernel kernel(Real(0.1));
  const Real eps = sizeof(Real) == 8 ? Real(1e-7) : Real(1e-4);
  for (const Vector3r& x : {Vector3r(Real(0.01), Real(0.015), Real(0.005)), Vector3r(Real(0.03), Real(-0.05), Real(0.02))}) {
    const Vector3r g = kernel.gradW(x);
    for (int d = 0; d < 3; ++d) {
      Vector3r e = Vector3r::Zero();
      e[d] = eps;
      const Real fd = (kernel.W(x + e) - kernel.W(x - e)) / (2 * eps);
      EXPECT_NEAR(g[d], fd, 1e-3 * kernel.W0() / Real(0.1));
    }
  }
}

TEST(CubicSplineKernel, GradientIntegratesToZeroAndHasUnitFirstMoment) {
  // int grad W dV = 0 and int x (x) grad W dV = -I (consistency of SPH derivatives).
  const CubicSplineKernel kernel(Real(0.1));
  const double gx = integrateOverSupport(Real(0.1), 60, [&](const Vector3r& x) { return double(kernel.gradW(x)[0]); });
  const double moment = integrateOverSupport(Real(0.1), 60, [&](const Vector3r& x) { return double(x[0] * kernel.gradW(x)[0]); });
  EXPECT_NEAR(gx, 0, 1e-9);
  EXPECT_NEAR(moment, -1, 5e-3);
}

TEST(CubicSplineKernel, DWdrIsTheRadialDerivative) {
  const CubicSplineKernel kernel(Real(0.1));
  const Real eps = sizeof(Real) == 8 ? Real(1e-7) : Real(1e-4);
  for (Real r : {Real(0.001), Real(0.02), Real(0.049), Real(0.051), Real(0.08), Real(0.099)}) {
    EXPECT_NEAR(kernel.dWdr(r), (kernel.W(r + eps) - kernel.W(r - eps)) / (2 * eps), 1e-3 * kernel.W0() / kernel.supportRadius()) << r;
    // Float: the two take different roundings (measured 8e-8 relative, at r = 0.049).
    EXPECT_NEAR(kernel.dWdr(r), kernel.gradW(Vector3r(r, 0, 0))[0],
                test::roundoff(1e-9 * kernel.W0() / kernel.supportRadius(), 4 * test::kFloatEps * std::abs(kernel.dWdr(r))));
  }
  EXPECT_EQ(kernel.dWdr(Real(0.11)), 0);
}

// The batch form the neighbour search uses (Kernel::evaluate, vectorised, both spline pieces
// computed and one picked) gives the scalar functions' bits at every distance a list can hold and
// at the pieces' edges: r = 0, the r < 1e-9 h cut, q = 1/2, q = 1 and beyond, and a tail that is
// not a whole vector.
TEST(CubicSplineKernel, BatchEvaluationHasTheScalarFunctionsBits) {
  const Real h = Real(0.05);
  const CubicSplineKernel kernel(h);
  std::vector<Real> r = {0, Real(1e-12), Real(0.5) * h, std::nextafter(Real(0.5) * h, Real(1)), h, std::nextafter(h, Real(1)),
                         Real(1.5) * h};
  for (int i = 0; i < 4001; ++i) r.push_back(Real(1.2) * h * Real(i) / Real(4000));
  std::vector<Real> g(r.size()), w(r.size()), gOnly(r.size());
  kernel.evaluate(r.data(), r.size(), g.data(), w.data());
  kernel.evaluate(r.data(), r.size(), gOnly.data(), nullptr);
  for (std::size_t a = 0; a < r.size(); ++a) {
    ASSERT_EQ(g[a], kernel.gradFactor(r[a])) << "r = " << r[a];
    ASSERT_EQ(gOnly[a], kernel.gradFactor(r[a])) << "r = " << r[a];
    ASSERT_EQ(w[a], kernel.W(r[a])) << "r = " << r[a];
  }
}
