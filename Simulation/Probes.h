// Probes: what a user measures at a boundary, sampled during the run and written to
// OUTPUT/probes.csv (docs/probes.md). Three kinds, chosen per probe in the scene's "probes" array:
//
//   pressure  the wall pressure on a static boundary surface around `position`: the normal
//             component of the impulses the pressure solve gave the boundary (the reaction of
//             its boundary term, Eq. (35) for the consistent treatment, Eq. (16) for mirroring
//             and extrapolation) during the step, divided by dt and by the surface area it acts
//             on. Both are weighted with w(t) = (1 - t^2 / R^2)^2 of the distance t from the probe
//             in the surface's tangent plane, so the reading is the pressure averaged over a
//             disc of radius R (default 2h) and not the count of samples that happen to fall
//             inside a sharp circle. The area integral int w dA is taken over the probed object's
//             own surface (a probe near an edge averages over the part of the disc that is wall).
//   level     the free-surface height on the vertical line (along -gravity) through `position`:
//             the highest point above `position` where the SPH colour field
//             c(x) = sum_j (m_j / rho_j) W(x - x_j) reaches 1/2; `position`'s own height where no
//             such point exists. A lone droplet (c <= 0.26 at its centre) does not count.
//   force     total force and torque of the fluid's pressure on one boundary object (static or
//             moving): the sum of the same impulses over the object's samples, divided by dt;
//             the torque about `point` (default: the object's centre of volume, a moving body's
//             current centre of mass), taken at the fluid particles as the rigid-body coupling
//             does. An optional `region` box keeps only the load on the part of the object
//             inside it (one wall of a tank, a section of a gate): the samples inside it, for
//             volume maps the share of each virtual particle's load whose surface lies inside.
//
// Loads come from the pressure solver's reaction, not from the particles' pressure values, so
// they obey momentum balance whatever the boundary pressure treatment: at rest the floor carries
// the fluid's weight.
#pragma once
#include <string>
#include <vector>

#include "Simulation/BoundaryModel.h"
#include "Simulation/Params.h"

namespace consph {

enum class ProbeKind { Pressure, Level, Force };

struct ProbeDescription {
  std::string name;
  std::string path;  // JSON path, for messages
  ProbeKind kind = ProbeKind::Pressure;
  Vector3r position = Vector3r::Zero();  // pressure, level
  Real radius = 0;                       // pressure: m; 0: twice the kernel support
  std::string boundary;                  // force: the object's name
  bool hasPoint = false;                 // force: torque reference given
  Vector3r point = Vector3r::Zero();
  bool hasRegion = false;                // force: only samples inside [regionMin, regionMax]
  Vector3r regionMin = Vector3r::Zero(), regionMax = Vector3r::Zero();
};

// The scene's "probes" array (null: none). Names must be unique and non-empty.
std::vector<ProbeDescription> parseProbes(const json& probes, const LogSink& log);

class Probes {
 public:
  // Resolves every probe against the scene's objects: the surface and area of pressure probes,
  // the object of force probes. Throws InputError naming the probe's JSON path when a pressure
  // probe is not on a static surface or a force probe names no object.
  Probes(std::vector<ProbeDescription> probes, const std::vector<BoundaryObject>& objects, Real supportRadius,
         const Vector3r& gravity);

  bool empty() const { return probes_.empty(); }
  // Whether any probe reads wall loads (the solver must then report its boundary impulses).
  bool readsLoads() const { return readsLoads_; }
  // Force probes take the torque about a moving object's current centre of mass.
  void setObjectCentre(std::size_t object, const Vector3r& centre);

  // After the pressure solve, before the boundary moves: pressure and force probes from the
  // impulses per fluid-boundary pair of this step (`impulses[e]` for the pair e = (i, k) of
  // `lists`, the impulse on sample k).
  // A region takes what the boundary model says acts inside it (BoundaryModel::impulseInBox).
  void measureLoads(const NeighborLists& lists, const std::vector<Vector3r>& fluidPositions, const BoundaryModel& boundary,
                    const std::vector<Vector3r>& impulses, Real dt);
  // At the end of a step: level probes from the fluid's positions.
  void measureLevels(const FluidModel& fluid, const CubicSplineKernel& kernel);

  // CSV columns after "time" (force probes as NAME.fx ... NAME.tz) and their latest values.
  const std::vector<std::string>& columns() const { return columns_; }
  const std::vector<double>& values() const { return values_; }
  json latest() const;  // {column: value}
  // A probes.csv row: pressure and force columns as their means over the window since the last
  // row (the impulse over the window divided by its length: what a sensor sampling at
  // output.probeFps and integrating between samples reads, free of the step-to-step swing of
  // the solver's reaction), levels as they are now; a window of one step gives values().
  std::vector<double> windowValues() const;
  void startWindow();
  // The window's state (checkpoints: a restarted run writes the same rows).
  struct Window {
    std::vector<double> impulses;  // per column: sum of value x dt (loads only)
    double time = 0;               // s
    std::size_t steps = 0;
  };
  const Window& window() const { return window_; }
  void setWindow(Window w) { window_ = std::move(w); }

 private:
  struct PressureGeometry {
    std::size_t object = 0;
    Vector3r centre = Vector3r::Zero(), normal = Vector3r::Zero();  // on the surface; normal into the fluid
    Real radius = 0, weightedArea = 0;                               // m, m^2 (int w dA)
  };
  Real weight(Real t2, Real radius) const;
  // Probe p's load columns from column_[p] on: 6 for a force, 1 for a pressure, 0 for a level.
  std::size_t loadColumns(std::size_t p) const {
    return probes_[p].kind == ProbeKind::Force ? 6 : probes_[p].kind == ProbeKind::Pressure ? 1 : 0;
  }

  std::vector<ProbeDescription> probes_;
  std::vector<PressureGeometry> pressure_;  // per probe (used by pressure probes)
  std::vector<Index> forceObject_;          // per probe (used by force probes)
  std::vector<Index> column_;               // per probe: its first column
  std::vector<Vector3r> objectCentre_;      // per object: default torque reference
  std::vector<std::string> columns_;
  std::vector<double> values_;
  Vector3r up_ = Vector3r::UnitY();
  Real supportRadius_ = 0;
  bool readsLoads_ = false;
  Window window_;
};

}  // namespace consph
