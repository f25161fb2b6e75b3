#include "Plugins/Vorticity/VorticityConfinement_Macklin2013.h"

#include <Eigen/Geometry>  // cross

#include "Simulation/ParamBinding.h"
#include "Simulation/PluginRegistry.h"
#include "Utilities/ParallelFor.h"

namespace consph {

namespace {
const PluginRegistration<NonPressureForce> registration{
    "VorticityConfinement", "vorticity confinement (Fedkiw et al. 2001, SPH form of Macklin & Mueller 2013)",
    VorticityConfinement_Macklin2013::parameters(),
    [](const Params& p, const PluginContext&) -> std::unique_ptr<NonPressureForce> {
      return std::make_unique<VorticityConfinement_Macklin2013>(p);
    }};

// |eta| below this fraction of |omega_i| / h counts as a uniform vorticity (no direction).
constexpr Real kUniformVorticity = Real(1e-6);
}  // namespace

const BoundParams<VorticityConfinement_Macklin2013>& VorticityConfinement_Macklin2013::bound() {
  static const BoundParams<VorticityConfinement_Macklin2013> table{
      bind({"vorticity", ParamType::Real, 0.01, "confinement strength eps, m/s", 0, 1e3},
           &VorticityConfinement_Macklin2013::epsilon_),
  };
  return table;
}

std::vector<ParamSpec> VorticityConfinement_Macklin2013::parameters() { return bound().specs(); }

VorticityConfinement_Macklin2013::VorticityConfinement_Macklin2013(const Params& p) { bound().assign(p, *this); }

void VorticityConfinement_Macklin2013::addAccelerations(StepContext& ctx) {
  const FluidView& f = ctx.fluid;
  const auto& fn = ctx.fluidNeighbors;
  const std::size_t n = f.size();
  omega_.resize(f.size());
  omegaNorm_.resize(f.size());
  // omega_i = curl v.
  parallelFor(n, [&](std::size_t i) {
    const Vector3r vi = f.velocities[i], xi = f.positions[i];
    Vector3r w = Vector3r::Zero();
    for (Index e = fn.begin(i); e < fn.end(i); ++e) {
      const Index j = fn.indices[e];
      w += f.masses[j] * (vi - f.velocities[j]).cross(fn.gradient(e, xi - f.positions[j]));
    }
    omega_[i] = w / f.densities[i];
    omegaNorm_[i] = omega_[i].norm();
  });
  // a_i += eps N_i x omega_i, N = grad |omega| / |grad |omega||.
  const Real h = ctx.kernel.supportRadius();
  parallelFor(n, [&](std::size_t i) {
    const Real wi = omegaNorm_[i];
    if (wi == Real(0)) return;
    Vector3r eta = Vector3r::Zero();
    const Vector3r xi = f.positions[i];
    for (Index e = fn.begin(i); e < fn.end(i); ++e) {
      const Index j = fn.indices[e];
      eta += (f.masses[j] * (omegaNorm_[j] - wi)) * fn.gradient(e, xi - f.positions[j]);
    }
    eta /= f.densities[i];
    const Real etaNorm = eta.norm();
    if (etaNorm * h <= kUniformVorticity * wi) return;
    f.accelerations[i] += epsilon_ * (eta / etaNorm).cross(omega_[i]);
  });
}

}  // namespace consph
