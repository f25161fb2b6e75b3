#include "Simulation/Emitter.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

namespace consph {

double Emitter::pointsAcross(Real extent, Real spacing) { return std::max(1.0, std::floor(double(extent) / double(spacing) + 1e-6)); }

double Emitter::layersUntil(const EmitterDescription& d, Real spacing, Real stopAt) {
  const double active = std::max(0.0, double(std::min(d.end, stopAt)) - double(d.start));
  // The scene's times, speed and spacing are stored in Real, each within half an ulp: in float a
  // layer due exactly at the end time (stopAt 0.7 s at 2 m/s and a spacing of 0.025 m: the 57th)
  // must not fall to that rounding, so the tolerance covers a few of Real's ulps of the count too.
  const double layers = active * double(d.speed) / double(spacing);
  return std::floor(layers * (1 + 4 * double(std::numeric_limits<Real>::epsilon())) + 1e-6) + 1;
}

double Emitter::estimateCapacity(const EmitterDescription& d, Real spacing, Real stopAt) {
  const double across = pointsAcross(d.circle ? 2 * d.radius : d.width, spacing);
  const double along = pointsAcross(d.circle ? 2 * d.radius : d.height, spacing);
  return across * along * layersUntil(d, spacing, stopAt);
}

Emitter::Emitter(const EmitterDescription& d, Real spacing, Real stopAt) : d_(d), spacing_(spacing) {
  // Nozzle axes: e1 horizontal for a horizontal jet (direction x y), e2 = direction x e1.
  const Vector3r dir = d_.direction;
  Vector3r e1 = dir.cross(Vector3r::UnitY());
  if (e1.norm() < Real(0.1)) e1 = dir.cross(Vector3r::UnitZ());
  e1.normalize();
  const Vector3r e2 = dir.cross(e1).normalized();
  // A centred lattice: n points along an extent L, spaced like the fluid blocks, symmetric about the centre.
  // (Simulation refuses nozzles whose estimateCapacity does not fit before building one.)
  const int n1 = int(pointsAcross(d_.circle ? 2 * d_.radius : d_.width, spacing_));
  const int n2 = int(pointsAcross(d_.circle ? 2 * d_.radius : d_.height, spacing_));
  for (int a = 0; a < n1; ++a)
    for (int b = 0; b < n2; ++b) {
      const Real u = (a - Real(n1 - 1) / 2) * spacing_, v = (b - Real(n2 - 1) / 2) * spacing_;
      // A particle belongs to the circle when its cell's centre is inside it.
      if (d_.circle && u * u + v * v > d_.radius * d_.radius) continue;
      layerPoints_.push_back(d_.position + u * e1 + v * e2);
    }
  maxLayers_ = std::size_t(layersUntil(d_, spacing_, stopAt));
  pending_ = spacing_;  // the first layer leaves at `start`
}

void Emitter::extendTo(Real endTime) { maxLayers_ = std::max(maxLayers_, std::size_t(layersUntil(d_, spacing_, endTime))); }

std::size_t Emitter::emit(FluidModel& fluid, double time, Real dt, Index& nextId) {
  if (time + dt <= d_.start || time >= d_.end) return 0;
  const double t0 = std::max(time, double(d_.start)), t1 = std::min(time + dt, double(d_.end));
  pending_ += d_.speed * (t1 - t0);
  const Real mass = fluid.density0() * spacing_ * spacing_ * spacing_;
  const Vector3r velocity = d_.speed * d_.direction;
  std::size_t emitted = 0;
  // Small tolerance: steps that add up to exactly one spacing must emit their layer.
  while (pending_ >= spacing_ * (1 - 1e-6) && layersEmitted_ < maxLayers_) {
    pending_ -= spacing_;
    // The layer left the nozzle `pending_` ago in distance: place it that far downstream.
    const Vector3r offset = Real(std::max(pending_, 0.0)) * d_.direction;
    const std::size_t base = fluid.size();
    fluid.resize(base + layerPoints_.size());
    for (std::size_t p = 0; p < layerPoints_.size(); ++p) {
      fluid.positions[base + p] = layerPoints_[p] + offset;
      fluid.velocities[base + p] = velocity;
      fluid.masses[base + p] = mass;
      fluid.ids[base + p] = nextId++;
    }
    emitted += layerPoints_.size();
    ++layersEmitted_;
  }
  return emitted;
}

}  // namespace consph
