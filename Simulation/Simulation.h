// A Simulation owns everything one run needs: the fluid, the boundary, the neighbour lists, the
// plugins and the output. No global state, so several simulations can live in one process.
#pragma once
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "Simulation/Emitter.h"
#include "Simulation/MovingBodies.h"
#include "Simulation/PluginRegistry.h"
#include "Simulation/Probes.h"
#include "Simulation/ResourceEstimate.h"
#include "Simulation/Scene.h"
#include "Simulation/SpeedScale.h"
#include "Utilities/Log.h"

namespace consph {

class FrameSeries;
class LineFile;
class RigidBodyGuard;

// Accumulated figures of a run (the CLI's summary, Python's sim.summary()).
struct SimulationStats {
  std::size_t steps = 0;
  double wallSeconds = 0;
  long long pressureIterations = 0, divergenceIterations = 0;
  double densityErrorSum = 0, densityErrorMax = 0;  // fraction of rho0, over measured steps
  std::size_t densityErrorSamples = 0;
  std::size_t iterationCapHits = 0, consecutiveCapHits = 0;
  // Steps an explicit force's local stability bound shortened (NonPressureForce::stepLimit).
  std::size_t stabilityLimitedSteps = 0;
  std::size_t boundaryLimitedSteps = 0;  // steps the boundary's approachStepLimit shortened
  std::size_t particlesEmitted = 0, particlesRemoved = 0;  // by emitters / removeOutside
  std::size_t particlesDroppedInsideBodies = 0;            // at start-up, inside closed bodies
  // seconds per phase
  double neighbourSearch = 0, densities = 0, divergenceSolve = 0, nonPressureForces = 0, pressureSolve = 0,
         integration = 0, exportTime = 0, rigidBodies = 0, emission = 0, probes = 0;
};

class Simulation {
 public:
  explicit Simulation(SceneDescription scene, const PluginRegistry& plugins = builtinPlugins(),
                      LogSink log = stderrLogSink(false));
  ~Simulation();
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  // One time step, top to bottom: emitters, neighbours, densities, (divergence solve),
  // non-pressure forces, time step, pressure solve, rigid-body coupling, integration, particle
  // removal, checks, export.
  void step();
  // Makes the emitters' budgets (and the reserved particle storage) cover a run until `until`
  // when that is past the end time they cover (at first the scene's stopAt): `--stop-at` and
  // Python's run(until=...) past stopAt must not cut a jet short. Growing the storage may move
  // the fields' data (NumPy views taken before become stale; Python raises StaleViewError at
  // once). Refuses (InputError) a budget past the resource limit, like the scene's own.
  void extendRunTo(double until);
  // Steps until `until` (simulated seconds), extendRunTo(until) first; `progress` is called after
  // every step; `stop` (optional) is asked after every step and ends the run early when true.
  void run(double until, const std::function<void(const Simulation&)>& progress = {}, const std::function<bool()>& stop = {});
  // Whether run(until) would stop now: half a minimum step early, so no sliver of a step is left.
  bool reached(double until) const { return time_ >= until - 0.5 * scene_.minTimeStep; }

  double time() const { return time_; }
  Real dt() const { return dt_; }
  // The largest step the adaptive step may take, s (see chooseTimeStepCap).
  Real timeStepCap() const { return timeStepCap_; }
  std::size_t stepCount() const { return stats_.steps; }
  FluidModel& fluid() { return *fluid_; }
  const FluidModel& fluid() const { return *fluid_; }
  BoundarySamples& boundary() { return boundaryModel_->samples(); }
  const BoundaryModel& boundaryModel() const { return *boundaryModel_; }
  const SceneDescription& scene() const { return scene_; }
  // Fluid particles deeper than r inside a static object's solid (leaked through a wall), now:
  // counted when asked (the summary asks once), not per step.
  std::size_t particlesLost() const;
  const SimulationStats& stats() const { return stats_; }
  PressureSolver& pressureSolver() { return *pressureSolver_; }
  const NeighborLists& fluidNeighbors() const { return fluidNeighbors_; }
  const NeighborLists& boundaryNeighbors() const { return boundaryNeighbors_; }
  const CubicSplineKernel& kernel() const { return kernel_; }
  const LogSink& log() const { return log_; }
  // The moving boundary objects (dynamic and animated bodies); null when every object is static.
  const MovingBodies* movingBodies() const { return bodies_.get(); }
  MovingBodies* movingBodies() { return bodies_.get(); }
  // The scene's probes; null when it has none.
  const Probes* probes() const { return probes_.get(); }

  // Appends a force (e.g. one written in Python) after the scene's forces.
  void addForce(std::unique_ptr<NonPressureForce> force);

  // Output: frames at scene.output.fps into scene.output.directory (when enabled).
  void setOutputDirectory(const std::string& dir);
  void setOutputEnabled(bool enabled);
  void setOutputFps(Real fps);
  // Writes the current state to one frame file (atomically) in the format its extension names
  // (.vtu, .ply, .bgeo, .bgeo.gz): the scene's output.attributes, at the build's precision (a
  // snapshot; .bgeo is float32 always).
  void exportFrame(const std::string& path);

  // Checkpoints (Simulation/Checkpoint.cpp): everything the next steps depend on (every
  // registered particle field of the fluid, which holds the plugins' persistent state such as
  // DFSPH's warm starts; the bodies; the emitters; time, step count and the time-step state), so
  // that a restarted run continues bit for bit. Written atomically.
  void saveCheckpoint(const std::string& path) const;
  // Continues from a checkpoint of the same scene (the scene file may differ in output.* and
  // simulation.stopAt only); InputError naming the first difference otherwise. Called before
  // the first step (the constructor does it for scene.restartFrom).
  void restoreCheckpoint(const std::string& path);
  // The checkpoints written so far at output.checkpointInterval (OUTPUT/checkpoint_NNNNN.state).
  std::size_t checkpointsWritten() const { return checkpointsWritten_; }
  // Fills the particle field "pressure" (the pressure field to read: frames, Python, the
  // tests) from the solver's pressures, unless it is up to date with the current step;
  // every frame does it itself.
  void updatePressureField();

  // The summary figures (the CLI prints them; --summary-json writes them).
  json summary() const;

  // The scene's largest speed from its start state (Simulation/SpeedScale.h).
  const SpeedScale& speedScale() const { return speedScale_; }

  // Domain outside which a particle counts as escaped (a blow-up).
  bool hasDomain() const { return hasDomain_; }

 private:
  ResourceEstimate estimateResources(Real endTime) const;
  void initializeFluid();
  // The dynamic bodies' checks (speed, domain, NaN) and the warning for overlaps at t = 0.
  void guardBodies();
  // InputError when the initial fluid or an emitter lies outside the escape domain.
  void checkStartInsideDomain() const;
  // The cap of the adaptive step: maxTimeStep when the scene gives it, else the bound from the
  // resolution and the physics (CFL at the speed scale, explicit forces' stability).
  void chooseTimeStepCap();
  // The CFL step cflFactor 0.4 (2r) / speed.
  Real cflTimeStep(Real cflFactor, Real speed) const { return cflFactor * Real(0.4) * 2 * scene_.particleRadius / speed; }
  void dropParticlesInsideBodies();
  void emitParticles();
  void coupleRigidBodies(StepContext& ctx);
  void removeParticlesOutside();
  void findNeighbors();
  void computeDensities();
  void computeNonPressureAccelerations(StepContext& ctx);
  void updateTimeStep();
  void integrate();
  void checkState();
  void writeFrameIfDue();
  void writeCheckpointIfDue();
  void measureWallLoads(StepContext& ctx);
  // The first line(s) of a restarted run's probes.csv: `header` and the rows of the file at
  // `path` up to simulated time `time` (only `header` when the file is missing or its header differs).
  static std::string probeRowsUpTo(const std::string& path, const std::string& header, double time);
  void writeProbeRowIfDue();
  StepContext makeContext();

  SceneDescription scene_;
  PluginRegistry plugins_;
  LogSink log_;
  CubicSplineKernel kernel_;
  std::unique_ptr<FluidModel> fluid_;
  std::unique_ptr<BoundaryModel> boundaryModel_;
  std::unique_ptr<PressureSolver> pressureSolver_;
  std::vector<std::unique_ptr<NonPressureForce>> forces_;
  PointGrid fluidGrid_;
  NeighborLists fluidNeighbors_, boundaryNeighbors_;
  PaddedNeighborLists paddedFluidNeighbors_;  // fluidNeighbors_ in blocks (StepContext::paddedFluidNeighbors)
  std::unique_ptr<FrameSeries> writer_, bodyWriter_;
  std::string bodyCsv_;  // every frame's body rows so far (rewritten atomically per frame)
  std::unique_ptr<MovingBodies> bodies_;
  std::unique_ptr<RigidBodyGuard> bodyGuard_;  // null without dynamic bodies
  SpeedScale speedScale_;                      // the scene's largest speed, from its start state
  std::vector<Vector3r> pairImpulses_;  // per fluid-boundary pair, this step (two-way coupling, probes)
  std::vector<Real>* pressureField_ = nullptr;  // the exported field "pressure" (updatePressureField)
  std::size_t pressureFieldStep_ = ~std::size_t(0);  // the step it was computed after (~0: never)
  std::unique_ptr<Probes> probes_;
  std::unique_ptr<LineFile> probeFile_;  // OUTPUT/probes.csv
  std::size_t nextProbeRow_ = 0;
  std::vector<Emitter> emitters_;
  Index nextId_ = 0;                    // id of the next emitted particle
  double emittersEndTime_ = 0;          // the end time the emitters' budgets and the storage cover

  // The clock is double in both builds: in float, t + dt loses dt's last digits as t grows (at
  // t = 100 s, whose ulp is 7.6e-6 s, a 1 ms step is off by up to 0.4 % of itself), and emitters
  // and frames read it.
  double time_ = 0;
  Real dt_ = 0, dtPrevious_ = 0, timeStepCap_ = 0;
  int lastPressureIterations_ = 0;  // the last step's density solve, for timeStepControl "iterations"
  Real densityRelaxationTime_ = 0;  // s, see chooseTimeStepCap
  bool hasDomain_ = false;
  Vector3r domainMin_, domainMax_;
  std::size_t nextFrame_ = 0;
  std::size_t nextCheckpoint_ = 1;  // checkpoint k is due at t = k output.checkpointInterval
  std::size_t checkpointsWritten_ = 0;
  bool restarted_ = false;          // continued from a checkpoint: its output folder is its own
  // A restarted run's frame lists and body rows as its checkpoint had them, for the first
  // setOutputDirectory into the folder the checkpoint was written for.
  struct ResumedOutput {
    bool pending = false;
    std::string directory, bodyCsv;
    std::size_t nextFrame = 0;
    std::vector<std::pair<double, std::string>> frames, bodyFrames;
  } resumed_;
  std::string ownedDirectory_;  // the output folder claimed (claimOutputFolder) by this simulation
  SimulationStats stats_;
};

// Builds the simulation of a scene file with --set style overrides.
std::unique_ptr<Simulation> loadSimulation(const std::string& scenePath,
                                           const std::vector<std::pair<std::string, std::string>>& overrides,
                                           LogSink log, const PluginRegistry& plugins = builtinPlugins());

}  // namespace consph
