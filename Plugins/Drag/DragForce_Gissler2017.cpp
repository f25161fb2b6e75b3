#include "Plugins/Drag/DragForce_Gissler2017.h"

#include <cmath>
#include <numbers>

#include "Simulation/ParamBinding.h"
#include "Simulation/PluginRegistry.h"
#include "Utilities/ParallelFor.h"

namespace consph {

namespace {
const PluginRegistration<NonPressureForce> registration{
    "Gissler2017", "air drag of droplets and surface particles (Gissler et al. 2017)", DragForce_Gissler2017::parameters(),
    [](const Params& p, const PluginContext& c) -> std::unique_ptr<NonPressureForce> {
      return std::make_unique<DragForce_Gissler2017>(p, c);
    }};

// A particle with this many neighbours or more is a full surface element (Eq. 10: 2/3 of 38).
constexpr Real kFullNeighbors = Real(38) * 2 / 3;
}  // namespace

const BoundParams<DragForce_Gissler2017>& DragForce_Gissler2017::bound() {
  static const BoundParams<DragForce_Gissler2017> table{
      bind({"drag", ParamType::Real, 1.0, "scale c of the drag force, dimensionless (1: the published model)", 0, 1e6},
           &DragForce_Gissler2017::drag_),
      bind({"airVelocity", ParamType::Vector3, json::array({0, 0, 0}), "velocity of the surrounding air, m/s", -1e6, 1e6},
           &DragForce_Gissler2017::airVelocity_),
  };
  return table;
}

std::vector<ParamSpec> DragForce_Gissler2017::parameters() { return bound().specs(); }

DragForce_Gissler2017::DragForce_Gissler2017(const Params& p, const PluginContext& c) {
  bound().assign(p, *this);
  const Real pi = std::numbers::pi_v<Real>;
  const Real rhoL = c.fluid->density0();
  diameter_ = 2 * c.particleRadius;
  L_ = std::cbrt(Real(3) / (4 * pi)) * diameter_;
  // Eqs. (6)-(8): the droplet's largest deformation per unit |v_rel|^2, a per-scene constant.
  const Real td = 2 * rhoL * L_ * L_ / (cD * liquidViscosity);
  const Real omega = std::sqrt(std::max(cK * surfaceTension / (rhoL * L_ * L_ * L_) - 1 / (td * td), Real(0)));
  const Real tMax = -2 * (std::atan(std::sqrt(td * td * omega * omega + 1) + td * omega) - pi) / omega;
  const Real cDef = 1 - std::exp(-tMax / td) * (std::cos(omega * tMax) + std::sin(omega * tMax) / (omega * td));
  yCoefficient_ = cF * airDensity * L_ / surfaceTension * cDef / (cK * cB);
}

void DragForce_Gissler2017::addAccelerations(StepContext& ctx) {
  const FluidView& f = ctx.fluid;
  const auto& fn = ctx.fluidNeighbors;
  const auto& bn = ctx.boundaryNeighbors;
  const Real pi = std::numbers::pi_v<Real>;
  parallelFor(f.size(), [&](std::size_t i) {
    const Vector3r vRel = airVelocity_ - f.velocities[i];
    const Real speed = vRel.norm();
    if (speed <= Real(1e-6)) return;
    const Vector3r dir = vRel / speed;
    const Real yMax = std::min(yCoefficient_ * speed * speed, Real(1));  // Eq. (8)
    const Real re = 2 * std::max(airDensity * speed * L_ / airViscosity, Real(0.1));
    const Real cSphere = re <= 1000 ? 24 / re * (1 + std::pow(re, Real(2) / 3) / 6) : Real(0.424);
    const Real cLiu = cSphere * (1 + Real(2.632) * yMax);  // Eq. (9)
    // Eq. (10) and (13): blend droplet -> surface element with the neighbour count.
    const Real neighbours = Real(fn.count(i) + (bn.queryCount() > 0 ? bn.count(i) : 0));
    const Real fn_ = std::min(kFullNeighbors, neighbours) / kFullNeighbors;
    const Real cDrag = (1 - fn_) * cLiu + fn_;
    const Real h1 = L_ + cB * L_ * yMax;  // Eq. (12)
    const Real areaUnoccluded = (1 - fn_) * pi * h1 * h1 + fn_ * diameter_ * diameter_;
    // Eq. (15): occlusion by the neighbour most directly upstream.
    Real maxAlignment = 0;
    const Vector3r xi = f.positions[i];
    for (Index e = fn.begin(i); e < fn.end(i); ++e) {
      const Vector3r xij = xi - f.positions[fn.indices[e]];
      const Real len = xij.norm();
      if (len > 0) maxAlignment = std::max(maxAlignment, dir.dot(xij) / len);
    }
    const Real area = std::clamp(1 - maxAlignment, Real(0), Real(1)) * areaUnoccluded;  // Eq. (14)
    f.accelerations[i] += (drag_ * Real(0.5) * airDensity / f.masses[i] * speed * cDrag * area) * vRel;
  });
}

}  // namespace consph
