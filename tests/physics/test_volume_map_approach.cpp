// VolumeMap's approachTolerance: the step is at most as long as keeps the boundary density a
// particle moves into within the tolerance of the density solve's linear prediction. Towards a
// wall, and most in a corner, a volume map's boundary density grows faster than linearly; a
// particle sliding into the floor / far-wall corner of DamBreak.json at 4.4 m/s (0.53 r per
// step) was compressed to 1.54 rho0 beyond what the solve saw and thrown back at 12.8 m/s
// (bench/RESULTS.md). Here a slab of 72 particles runs along the floor into a corner at 4 m/s.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "Boundary/VolumeMapBoundary_Bender2019.h"
#include "TestUtil.h"

using namespace consph;

namespace {

struct CornerRun {
  double densest = 0;   // largest rho_i / rho0 over every particle and step
  double fastest = 0;   // m/s
  std::size_t steps = 0, limited = 0;
};

CornerRun slabIntoACorner(double approachTolerance) {
  json scene = json::parse(R"({
    "simulation": {"particleRadius": 0.025, "stopAt": 0.3,
                   "boundaryModel": {"type": "VolumeMap", "cache": ""}},
    "fluids": [{"blocks": [{"min": [0, 0, 0], "max": [0.3, 0.1, 0.3], "velocity": [4, 0, 0]}]}],
    "boundaries": [{"name": "tank", "box": {"min": [-0.05, -0.05, -0.05], "max": [0.9, 0.6, 0.35]}, "inverted": true}]
  })");
  scene["simulation"]["boundaryModel"]["approachTolerance"] = approachTolerance;
  auto sim = test::simulationFromJson(scene);
  const FluidModel& f = sim->fluid();
  CornerRun out;
  while (sim->time() < Real(0.3) - Real(1e-9)) {
    sim->step();
    for (std::size_t i = 0; i < f.size(); ++i) {
      out.densest = std::max(out.densest, double(f.densities[i] / f.density0()));
      out.fastest = std::max(out.fastest, double(f.velocities[i].norm()));
    }
  }
  out.steps = sim->stepCount();
  out.limited = sim->stats().boundaryLimitedSteps;
  std::printf("[ approach ] tolerance %.0f %%: %zu steps (%zu limited), densest %.3f rho0, fastest %.2f m/s\n", approachTolerance,
              out.steps, out.limited, out.densest, out.fastest);
  return out;
}

}  // namespace

// Measured 2026-12-06 (double, 2 threads): off, 98 steps, densest 1.692 rho0, fastest 9.04 m/s;
// at 1 %, 156 steps (125 limited), densest 1.034, fastest 8.01 (the run-up along the far wall);
// without the headroom a particle below (1 + e) rho0 may use, 204 steps, densest 1.014.
TEST(VolumeMapApproach, AParticleDrivenIntoACornerStaysNearRho0) {
  const CornerRun off = slabIntoACorner(0);
  EXPECT_EQ(off.limited, 0u);
  EXPECT_GT(off.densest, 1.3);  // what the limit is for: the linear prediction falls short
  const CornerRun on = slabIntoACorner(1);
  EXPECT_GT(on.limited, 0u);
  EXPECT_LT(on.densest, 1.05);
  EXPECT_LT(on.fastest, off.fastest);
}

namespace {

struct BodyLanding {
  double fastest = 0;    // m/s, the fluid's
  double shortest = 1;   // s, the shortest step
  std::size_t limited = 0;
};

// bench/stability.py's heavy-body row: a 0.1 m box of 100 rho0 dropped through 0.25 m of water
// onto the tank's floor, where it lands at ~2.5 m/s on the film under it.
BodyLanding heavyBoxLands(double approachTolerance) {
  json scene = json::parse(R"({
    "simulation": {"particleRadius": 0.025, "stopAt": 0.4,
                   "boundaryModel": {"type": "VolumeMap", "cache": ""}},
    "fluids": [{"blocks": [{"min": [0, 0, 0], "max": [0.4, 0.25, 0.4]}]}],
    "boundaries": [{"name": "tank", "box": {"min": [0, 0, 0], "max": [0.4, 0.8, 0.4]}, "inverted": true},
                   {"name": "body", "box": {"min": [0.15, 0.4, 0.15], "max": [0.25, 0.5, 0.25]}, "dynamic": true, "density": 1e5}]
  })");
  scene["simulation"]["boundaryModel"]["approachTolerance"] = approachTolerance;
  auto sim = test::simulationFromJson(scene);
  const FluidModel& f = sim->fluid();
  BodyLanding out;
  while (sim->time() < Real(0.4) - Real(1e-9)) {
    sim->step();
    out.shortest = std::min(out.shortest, double(sim->dt()));
    for (std::size_t i = 0; i < f.size(); ++i) out.fastest = std::max(out.fastest, double(f.velocities[i].norm()));
  }
  out.limited = sim->stats().boundaryLimitedSteps;
  std::printf("[ approach ] heavy box, tolerance %.0f %%: %zu steps (%zu limited), shortest %.2e s, fastest %.2f m/s\n",
              approachTolerance, sim->stepCount(), out.limited, out.shortest, out.fastest);
  return out;
}

}  // namespace

// Near a moving body the step is not shortened. Measured 2026-12-06 (double, 2 threads,
// bench/stability.py's row to 1 s): counted with the fluid's velocity relative to the body, the
// box's landing drove the step to the 1e-4 s minimum and the film it squeezed out to 346 m/s
// (16.0 m/s with the limit off); with the static walls alone, 17.2 m/s, the shortest step 0.5 ms;
// with the particles near the body left out as well (the code now), 13.9 m/s.
TEST(VolumeMapApproach, ABodyLandingOnTheFloorThroughWaterKeepsItsStep) {
  const BodyLanding off = heavyBoxLands(0);
  const BodyLanding on = heavyBoxLands(3);
  // The landing's fastest particle depends on the step chaotically even without the limit
  // (cflFactor 0.3 / 0.5 / 0.8: 56 / 40 / 110 m/s against 11.3 at the default; bench/RESULTS.md),
  // so what is asserted is that the limit leaves the step near the body alone, and that the
  // landing stays within twice the unlimited run's fastest (measured: 101 steps, 34 limited,
  // shortest 1.22 ms against 1.78, fastest 17.0 against 11.3 m/s).
  EXPECT_GT(on.limited, 0u);  // the splash along the tank's walls
  EXPECT_GT(on.shortest, 0.25 * off.shortest);
  EXPECT_LT(on.fastest, 2 * off.fastest);
}

// approachStepLimit's shortcut rests on each static map's densityBound: no point gets more
// boundary density from that map's virtual particle, placed as the limit places it. Checked at
// every point of a lattice of spacing r/2 over the corner run's tank and a support radius beyond
// its walls (into the solid, where V is the whole ball's and the bound is reached).
TEST(VolumeMapApproach, NoPointGetsMoreBoundaryDensityThanItsMapsBound) {
  json scene = json::parse(R"({
    "simulation": {"particleRadius": 0.025, "boundaryModel": {"type": "VolumeMap", "cache": ""}},
    "fluids": [{"blocks": [{"min": [0, 0, 0], "max": [0.3, 0.1, 0.3]}]}],
    "boundaries": [{"name": "tank", "box": {"min": [-0.05, -0.05, -0.05], "max": [0.9, 0.6, 0.35]}, "inverted": true}]
  })");
  auto sim = test::simulationFromJson(scene);
  const auto& model = dynamic_cast<const VolumeMapBoundary_Bender2019&>(sim->boundaryModel());
  const CubicSplineKernel& kernel = sim->kernel();
  const Real r = Real(0.025), h = kernel.supportRadius(), rho0 = sim->fluid().density0();
  ASSERT_EQ(model.mapCount(), 6u);  // the tank's six walls
  for (std::size_t p = 0; p < model.mapCount(); ++p) {
    const VolumeMap& map = model.pieceMap(p);
    const Real bound = model.pieceDensityBound(p);
    Real largest = 0;
    std::size_t sampled = 0;
    for (Real x = Real(-0.05) - h; x <= Real(0.9) + h; x += r / 2)
      for (Real y = Real(-0.05) - h; y <= Real(0.6) + h; y += r / 2)
        for (Real z = Real(-0.05) - h; z <= Real(0.35) + h; z += r / 2) {
          const Vector3r at(x, y, z);
          Real phi, volume;
          Vector3r phiGradient;
          if (!map.sampleValues(at, phi, phiGradient, volume)) continue;
          const Real s = std::max(phi + r / 2, 2 * r);
          const Real density = rho0 * volume * kernel.W(at - (at - s * phiGradient.normalized()));
          largest = std::max(largest, density);
          ++sampled;
          ASSERT_LE(density, bound) << "map " << p << " at " << at.transpose();
        }
    std::printf("[ approach ] map %zu: %zu points, largest boundary density %.4f rho0, bound %.4f rho0\n", p, sampled,
                double(largest / rho0), double(bound / rho0));
    EXPECT_GT(sampled, 1000u);
    EXPECT_GT(largest, Real(0.95) * bound);  // reached deep in the wall: the bound is not vacuous there
  }
}

// approachStepLimit may leave out the particles that cannot shorten the step (the bound above
// bounds their curvature): where the limit binds, i.e. lies below the step the other bounds give
// (longestUseful), it must be the same bits as with longestUseful infinite (where only particles
// whose curvature bound is not positive are left out, which add nothing), and elsewhere at least
// longestUseful. Checked at every step of the corner run, for steps around the limit and for the
// step the run took. (A bound too small by a third still passes this one; the test above is the
// bound's own.)
TEST(VolumeMapApproach, LeavingOutParticlesThatCannotBindKeepsTheLimit) {
  json scene = json::parse(R"({
    "simulation": {"particleRadius": 0.025, "stopAt": 0.3,
                   "boundaryModel": {"type": "VolumeMap", "cache": "", "approachTolerance": 1}},
    "fluids": [{"blocks": [{"min": [0, 0, 0], "max": [0.3, 0.1, 0.3], "velocity": [4, 0, 0]}]}],
    "boundaries": [{"name": "tank", "box": {"min": [-0.05, -0.05, -0.05], "max": [0.9, 0.6, 0.35]}, "inverted": true}]
  })");
  auto sim = test::simulationFromJson(scene);
  const Real infinity = std::numeric_limits<Real>::infinity();
  std::size_t binding = 0, checks = 0;
  while (sim->time() < Real(0.3) - Real(1e-9)) {
    sim->step();
    const auto limit = [&](Real longestUseful) {
      return sim->boundaryModel().approachStepLimit(sim->fluid(), sim->boundaryNeighbors(), sim->kernel(), longestUseful);
    };
    const Real full = limit(infinity);
    if (!std::isfinite(full)) continue;  // no particle curving into a wall this step
    for (const Real longestUseful : {Real(0.5) * full, full, Real(1.001) * full, Real(2) * full, Real(sim->dt())}) {
      const Real shortcut = limit(longestUseful);
      ++checks;
      if (full < longestUseful) {
        EXPECT_EQ(shortcut, full) << "t = " << sim->time() << ", longestUseful " << longestUseful;
        ++binding;
      } else {
        EXPECT_GE(shortcut, longestUseful) << "t = " << sim->time();
      }
    }
  }
  EXPECT_GT(binding, checks / 3);  // both branches were exercised
  EXPECT_LT(binding, checks);
}
