// A nozzle that emits fluid particles at a given velocity between a start and an end time: a
// rectangle or a circle filled with a square lattice of spacing 2r, perpendicular to the
// emission direction; a new layer leaves the nozzle every 2r / speed seconds. Its whole budget
// (until the run's end time) is known up front, so the fluid reserves it once and data pointers
// do not move; a run extended past that end time grows the budget once (Simulation::extendRunTo).
#pragma once
#include <string>
#include <vector>

#include "Simulation/FluidModel.h"

namespace consph {

struct EmitterDescription {
  std::string path;  // JSON path, for messages
  bool circle = false;
  Vector3r position = Vector3r::Zero();     // centre of the nozzle, m
  Vector3r direction = -Vector3r::UnitY();  // unit emission direction
  Real width = 0, height = 0;               // rectangle, m
  Real radius = 0;                          // circle, m
  Real speed = 1;                           // m/s
  Real start = 0, end = 0;                  // s
};

class Emitter {
 public:
  // `spacing`: the fluid's lattice spacing (simulation.particleSpacing times r).
  Emitter(const EmitterDescription& description, Real spacing, Real stopAt);
  // Particles this emitter can emit until min(end, stopAt): its budget.
  std::size_t capacity() const { return layerPoints_.size() * maxLayers_; }
  // Of the budget, the particles not emitted yet.
  std::size_t remaining() const { return layerPoints_.size() * (maxLayers_ - layersEmitted_); }
  // Grows the budget to the layers due until min(end, endTime) (a run past the scene's stopAt);
  // never shrinks it.
  void extendTo(Real endTime);
  std::size_t particlesPerLayer() const { return layerPoints_.size(); }
  // An upper bound of capacity() computed in floating point without building the emitter (the
  // nozzle's bounding square per layer), for the up-front resource estimate.
  static double estimateCapacity(const EmitterDescription& description, Real spacing, Real stopAt);
  // Emits the layers due in [time, time + dt): appends particles with ids from nextId on.
  // Returns how many it emitted.
  std::size_t emit(FluidModel& fluid, double time, Real dt, Index& nextId);

  // What changes while it emits (checkpoints save and restore it).
  struct State {
    std::size_t maxLayers, layersEmitted;
    double pending;
  };
  State state() const { return {maxLayers_, layersEmitted_, pending_}; }
  void setState(const State& s) {
    maxLayers_ = s.maxLayers;
    layersEmitted_ = s.layersEmitted;
    pending_ = s.pending;
  }

 private:
  // Lattice points across an extent, and layers emitted until min(end, stopAt), in floating point.
  static double pointsAcross(Real extent, Real spacing);
  static double layersUntil(const EmitterDescription& d, Real spacing, Real stopAt);

  EmitterDescription d_;
  Real spacing_;
  std::vector<Vector3r> layerPoints_;  // world positions of one layer at the nozzle
  std::size_t maxLayers_ = 0, layersEmitted_ = 0;
  // Length of fluid that has left the nozzle but is not emitted yet, m: in double in both builds,
  // like the clock, so that float runs emit the same layers (a float sum of ~1e3 steps drifts).
  double pending_;
};

}  // namespace consph
