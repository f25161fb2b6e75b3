// Section 3.4.1 of Bender, Westhofen, Jeske 2023: without boundaries, the constraint-based solver
// (Eqs. 18-28, unknowns lambda_i) and the classic IISPH / PPE solver (Eqs. 8-12, unknowns p_i)
// are the same iteration: p_i = lambda_i rho_i and identical velocities, to round-off.
// The classic form is the IISPH plugin itself; the constraint form is written out here, literally
// from the paper's equations (constraint gradients, Lagrange multipliers, v**).
#include <gtest/gtest.h>

#include <cstdio>
#include <limits>
#include <random>

#include "Plugins/Pressure/IISPH.h"
#include "tests/support/StandaloneStep.h"

using namespace consph;

namespace {

constexpr Real kRadius = Real(0.025), kRho0 = 1000, kDt = Real(0.002), kOmega = Real(0.5);
constexpr int kIterations = 25;

// A jittered, compressed block (spacing 1.9 r instead of 2 r) flowing together: the densities and
// the predicted densities exceed rho0, so the pressures are large and mostly active, while the
// free surface keeps some clamped to 0.
void makeBlock(test::StandaloneStep& s) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-0.1, 0.1);
  const int n = 9;
  const Real d = Real(1.9) * kRadius;
  FluidModel& f = s.fluid;
  f.resize(std::size_t(n * n * n));
  std::size_t p = 0;
  const Vector3r center = Vector3r::Constant(Real(0.5) * (n - 1) * d);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k, ++p) {
        f.positions[p] = Vector3r(i * d, j * d, k * d) + kRadius * Vector3r(Real(jitter(rng)), Real(jitter(rng)), Real(jitter(rng)));
        f.velocities[p] = -Real(0.5) * (f.positions[p] - center) + Vector3r(Real(jitter(rng)), Real(jitter(rng)), Real(jitter(rng)));
        f.masses[p] = kRho0 * 8 * kRadius * kRadius * kRadius;  // equal masses: Eq. (19) gives Eq. (12)
        f.ids[p] = Index(p);
      }
  s.update();
}

// The constraint form: returns lambda; leaves v(t + dt) in `velocities`.
std::vector<Real> constraintSolve(const test::StandaloneStep& s, std::vector<Vector3r>& velocities) {
  const FluidModel& f = s.fluid;
  const NeighborLists& nl = s.fluidNeighbors;
  const std::size_t n = f.size();
  const std::vector<Vector3r> vStar = velocities;
  // Eq. (19)'s left-hand factor (1 / rho_i)(|dC_i/dx_i|^2 + sum_j |dC_i/dx_j|^2), Eqs. (20), (21).
  std::vector<Real> k(n);
  for (std::size_t i = 0; i < n; ++i) {
    Vector3r dCdxi = Vector3r::Zero();
    Real sum = 0;
    for (Index e = nl.begin(i); e < nl.end(i); ++e) {
      const Vector3r dCdxj = f.masses[nl.indices[e]] * nl.gradient(e, f.positions[i] - f.positions[nl.indices[e]]);
      dCdxi -= dCdxj;
      sum += dCdxj.squaredNorm();
    }
    k[i] = (dCdxi.squaredNorm() + sum) / f.densities[i];
  }
  std::vector<Real> lambda(n, Real(0));
  std::vector<Vector3r> a(n), vss(n);
  auto accelerations = [&] {
    // Eq. (24): a_i^p = f_i^p / m_i = -sum_j m_j (lambda_i / rho_i + lambda_j / rho_j) grad W_ij.
    for (std::size_t i = 0; i < n; ++i) {
      a[i] = Vector3r::Zero();
      for (Index e = nl.begin(i); e < nl.end(i); ++e) {
        const Index j = nl.indices[e];
        a[i] -= f.masses[j] * (lambda[i] / f.densities[i] + lambda[j] / f.densities[j]) * nl.gradient(e, f.positions[i] - f.positions[j]);
      }
    }
  };
  for (int it = 0; it < kIterations; ++it) {
    accelerations();
    for (std::size_t i = 0; i < n; ++i) vss[i] = vStar[i] + kDt * a[i];  // Eq. (25)
    std::vector<Real> next(n);
    for (std::size_t i = 0; i < n; ++i) {
      // C_i** = rho0 - rho_i - dt sum_j m_j (v_i** - v_j**) . grad W_ij   (Eq. 26, first line)
      Real c = kRho0 - f.densities[i];
      for (Index e = nl.begin(i); e < nl.end(i); ++e) c -= kDt * f.masses[nl.indices[e]] * (vss[i] - vss[nl.indices[e]]).dot(nl.gradient(e, f.positions[i] - f.positions[nl.indices[e]]));
      // Eqs. (19), (22), (27): rho_i A_ii = -dt k_i; lambda_i += omega / (rho_i A_ii) C_i** / dt, clamped at 0.
      next[i] = k[i] > 0 ? std::max(lambda[i] - kOmega * c / (kDt * kDt * k[i]), Real(0)) : Real(0);
    }
    lambda = next;
  }
  accelerations();
  for (std::size_t i = 0; i < n; ++i) velocities[i] = vStar[i] + kDt * a[i];
  return lambda;
}

}  // namespace

TEST(ConstraintEquivalence, ConstraintAndClassicFormsGiveTheSamePressuresAndVelocities) {
  test::StandaloneStep s(kRadius, kRho0);
  makeBlock(s);
  std::vector<Vector3r> constraintVelocities = s.fluid.velocities;
  const std::vector<Real> lambda = constraintSolve(s, constraintVelocities);

  // The classic form: the IISPH plugin, a fixed number of iterations, no warm start, and the
  // paper's target rho0 for every particle (no overlap relief: the compressed block starts over
  // 1 % above rho0, where the relief would lower the plugin's target and not the equations').
  IISPH iisph(Params(json{{"maxError", 1e-6}, {"minIterations", kIterations}, {"maxIterations", kIterations},
                          {"omega", kOmega}, {"warmStart", false}, {"overlapReliefSpeed", 0}},
                     "pressureSolver", IISPH::parameters(), s.log));
  StepContext ctx = s.context(kDt);
  iisph.solve(ctx);
  ASSERT_EQ(iisph.stats().pressureIterations, kIterations);

  const FluidModel& f = s.fluid;
  Real pMax = 0, pDiff = 0, vMax = 0, vDiff = 0;
  std::size_t active = 0;
  for (std::size_t i = 0; i < f.size(); ++i) {
    const Real p = lambda[i] * f.densities[i];  // lambda_i = p_i / rho_i (Section 3.4.1)
    pMax = std::max(pMax, std::abs(f.pressures[i]));
    pDiff = std::max(pDiff, std::abs(f.pressures[i] - p));
    vMax = std::max(vMax, f.velocities[i].norm());
    vDiff = std::max(vDiff, (f.velocities[i] - constraintVelocities[i]).norm());
    active += f.pressures[i] > 0;
  }
  // Not a vacuous comparison: large pressures inside the block, some clamped at its surface.
  EXPECT_GT(pMax, 100 * kRho0 * kRadius);
  EXPECT_GT(active, f.size() / 3);
  EXPECT_LT(active, f.size());
  // Round-off: a few hundred operations per value, over kIterations iterations.
  const Real tolerance = 1e4 * std::numeric_limits<Real>::epsilon();
  std::printf("max p %g Pa, max |dp| %g Pa, max |v| %g m/s, max |dv| %g m/s, %zu of %zu active\n", double(pMax),
              double(pDiff), double(vMax), double(vDiff), active, f.size());
  EXPECT_LT(pDiff, tolerance * pMax) << "max |p - lambda rho| = " << pDiff << " of max p = " << pMax;
  EXPECT_LT(vDiff, tolerance * vMax) << "max |v_classic - v_constraint| = " << vDiff << " of max |v| = " << vMax;
}
