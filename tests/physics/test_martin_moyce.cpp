// Dam break with a column twice as high as wide (n^2 = 2) against Martin & Moyce (1952): the
// surge front Z = x / a over T = t sqrt(2 g / a), coarse (22 x 44 x 4 particles) so it runs in
// seconds. SPH fronts run slightly ahead of the experiment (no wall friction, no gate), so the
// test bounds the RMS difference and checks the front is never behind by more than 0.1.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "TestUtil.h"

using namespace consph;

TEST(MartinMoyce, SurgeFrontFollowsTheExperiment) {
  // Measured (T, Z), data/validation/martin_moyce_1952_front_n2.csv.
  std::vector<std::pair<double, double>> measured;
  std::ifstream csv(test::dataPath("validation/martin_moyce_1952_front_n2.csv"));
  ASSERT_TRUE(csv.good());
  for (std::string line; std::getline(csv, line);) {
    if (line.empty() || line[0] == '#' || line[0] == 'T') continue;
    std::stringstream s(line);
    double T, Z;
    char comma;
    s >> T >> comma >> Z;
    measured.emplace_back(T, Z);
  }
  ASSERT_GE(measured.size(), 10u);

  const double r = 0.005, d = 1.8566 * r, wall = 2 * r;  // d: the default lattice spacing
  const int nx = 22, ny = 44, nz = 4;
  const double a = nx * d, g = 9.81;
  const double up = 5e-7;
  json scene = {
      {"simulation",
       {{"particleRadius", r}, {"stopAt", 1}, {"pressureSolver", {{"type", "DFSPH"}, {"maxError", 0.05}}}}},
      {"fluids",
       {{{"forces", {{{"type", "StandardViscosity"}, {"viscosity", 1e-6}}}},
         {"blocks", {{{"min", {wall, wall, wall}}, {"max", {wall + nx * d + up, wall + ny * d + up, wall + nz * d + up}}}}}}}},
      {"boundaries", {{{"box", {{"min", {0, 0, 0}}, {"max", {1.2, 0.6, 2 * wall + nz * d}}}}, {"inverted", true}}}}};
  auto sim = test::simulationFromJson(scene);
  ASSERT_EQ(sim->fluid().size(), std::size_t(nx * ny * nz));

  const double timeScale = std::sqrt(2 * g / a);  // T = t timeScale
  const double tEnd = measured.back().first / timeScale;
  std::vector<double> times{0}, fronts{1};
  while (sim->time() < tEnd) {
    sim->step();
    Real front = 0;
    for (auto& x : sim->fluid().positions) front = std::max(front, x[0]);
    times.push_back(sim->time());
    fronts.push_back((front + 0.5 * d - wall) / a);
  }
  double sumSquares = 0, worstBehind = 0;
  for (auto [T, Z] : measured) {
    const double t = T / timeScale;
    std::size_t k = 1;
    while (k + 1 < times.size() && times[k] < t) ++k;
    const double w = (t - times[k - 1]) / (times[k] - times[k - 1]);
    const double Zsim = (1 - w) * fronts[k - 1] + w * fronts[k];
    sumSquares += (Zsim - Z) * (Zsim - Z);
    worstBehind = std::max(worstBehind, Z - Zsim);
    std::printf("Martin & Moyce: T = %.2f  Z measured %.2f  simulated %.3f\n", T, Z, Zsim);
  }
  const double rms = std::sqrt(sumSquares / double(measured.size()));
  std::printf("Martin & Moyce: RMS(Z) = %.3f, worst lag behind the experiment %.3f\n", rms, worstBehind);
  EXPECT_LT(rms, 0.2);
  EXPECT_LT(worstBehind, 0.1);
}
