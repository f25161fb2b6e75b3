// The worked example of docs/extending.md: a linear (Stokes) drag towards the air's velocity,
//   a_i -= k (v_i - v_air),
// the drag of a particle in a viscous medium at low Reynolds number (Stokes 1851: F = 6 pi mu R v,
// here lumped into one rate k = 6 pi mu R / m). A velocity relaxes as exp(-k t) towards v_air.
// Parameters: `coefficient` k, 1/s; `airVelocity` v_air, m/s. The test suite builds it into its
// own binary (tests/examples) and runs a scene naming it.
#pragma once
#include "Simulation/NonPressureForce.h"
#include "Simulation/Params.h"

namespace consph {

class LinearDrag final : public NonPressureForce {
 public:
  explicit LinearDrag(const Params& params);
  void addAccelerations(StepContext& ctx) override;
  static std::vector<ParamSpec> parameters();

 private:
  Real coefficient_;  // k, 1/s
  Vector3r airVelocity_;
};

}  // namespace consph
