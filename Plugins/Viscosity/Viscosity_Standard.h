// Standard SPH viscosity: the explicit velocity Laplacian of
//   J. P. Morris, P. J. Fox, Y. Zhu: Modeling low Reynolds number incompressible flows using SPH.
//   Journal of Computational Physics 136(1), 1997, 214-226
// (SPlisHSPlasH's "Standard" viscosity, after Monaghan 2005), in the symmetric form of
// ViscosityLaplacian.h, with an optional boundary viscosity towards the boundary samples:
//   a_i += nu (laplacian v)_i.
// Parameters: `viscosity` nu and `boundaryViscosity` nu_b, kinematic viscosities in m^2/s.
// Explicit: stable for dt <= 0.125 h^2 / nu (Morris et al. 1997, Section 2.3, h the smoothing
// length: half the cubic spline's support) in the bulk, the default cap; and every step for
// dt <= 2 / lambda_i at every particle (stepLimit): the local bound from the operator itself,
// which is lower at a free surface (docs/forces.md, "Stability"). Use Weiler2018 for very viscous fluids.
#pragma once
#include <limits>
#include <vector>

#include "Simulation/NonPressureForce.h"
#include "Simulation/Params.h"

namespace consph {

template <class Settings>
class BoundParams;

class Viscosity_Standard final : public NonPressureForce {
 public:
  explicit Viscosity_Standard(const Params& params);
  void addAccelerations(StepContext& ctx) override;
  Real maxStableTimeStep(const CubicSplineKernel& kernel) const override;
  Real stepLimit() const override { return stepLimit_; }
  bool readsPaddedNeighbors() const override { return kPackedPairSums; }  // packedFluidSumWithRate
  static std::vector<ParamSpec> parameters();

 private:
  // The parameters, each declared once with the member it sets (Simulation/ParamBinding.h).
  static const BoundParams<Viscosity_Standard>& bound();
  Real viscosity_, boundaryViscosity_;
  Real stepLimit_ = std::numeric_limits<Real>::infinity();  // s, of the last addAccelerations
  // This step's slots (x, y, z, m / rho) and (v, 0) of packedFluidSumWithRate; without
  // kPackedPairSums, positionsVolumes_ holds m / rho alone (ViscosityLaplacian.h).
  std::vector<Real> positionsVolumes_, velocities_;
};

}  // namespace consph
