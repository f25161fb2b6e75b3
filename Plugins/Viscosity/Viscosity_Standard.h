// Standard SPH viscosity: the explicit velocity Laplacian of
//   J. P. Morris, P. J. Fox, Y. Zhu: Modeling low Reynolds number incompressible flows using SPH.
//   Journal of Computational Physics 136(1), 1997, 214-226
// (SPlisHSPlasH's "Standard" viscosity, after Monaghan 2005), in the symmetric form of
// ViscosityLaplacian.h, with an optional boundary viscosity towards the boundary samples:
//   a_i += nu (laplacian v)_i.
// Parameters: `viscosity` nu and `boundaryViscosity` nu_b, kinematic viscosities in m^2/s.
// Explicit: stable for nu dt / h^2 small; use Weiler2018 for very viscous fluids.
#pragma once
#include "Simulation/NonPressureForce.h"
#include "Simulation/Params.h"

namespace consph {

class Viscosity_Standard final : public NonPressureForce {
 public:
  explicit Viscosity_Standard(const Params& params);
  void addAccelerations(StepContext& ctx) override;
  static std::vector<ParamSpec> parameters();

 private:
  Real viscosity_, boundaryViscosity_;
};

}  // namespace consph
