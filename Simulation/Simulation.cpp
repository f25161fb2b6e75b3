#include "Simulation/Simulation.h"

#include <omp.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "Simulation/FrameSeries.h"
#include "Simulation/LeakedParticles.h"
#include "Simulation/RigidBodyGuard.h"
#include "Simulation/SceneFile.h"
#include "Utilities/AxisAlignedBox.h"
#include "Utilities/LineFile.h"
#include "Utilities/OutputFolder.h"
#include "Utilities/ParallelFor.h"
#include "Utilities/Timer.h"
#include "Utilities/TriangleBvh.h"
#include "Utilities/VtkWriter.h"

namespace consph {

Simulation::Simulation(SceneDescription scene, const PluginRegistry& plugins, LogSink log)
    : scene_(std::move(scene)), plugins_(plugins), log_(std::move(log)), kernel_(4 * scene_.particleRadius) {
  const FluidDescription& fd = scene_.fluids.at(0);
  fluid_ = std::make_unique<FluidModel>(fd.name, fd.density0);
  pressureField_ = &fluid_->fields().add<Real>("pressure", FieldSorted | FieldExported, Real(0));
  const PluginContext context{fluid_.get(), scene_.particleRadius, kernel_.supportRadius(), log_,
                              scene_.particleSpacing * scene_.particleRadius, scene_.baseDir};
  boundaryModel_ = plugins_.boundaryModels.create(scene_.boundaryModel["type"].get<std::string>(), scene_.boundaryModel,
                                                  "simulation.boundaryModel", context, log_);
  // Before anything is allocated: refuse what cannot fit, with the estimate.
  refuseIfTooLarge(estimateResources(scene_.stopAt), scene_.maxParticles);
  emittersEndTime_ = scene_.stopAt;
  for (const EmitterDescription& e : fd.emitters) emitters_.emplace_back(e, scene_.particleSpacing * scene_.particleRadius, emittersEndTime_);
  initializeFluid();
  dropParticlesInsideBodies();

  boundaryModel_->initialize(scene_.boundaries, *fluid_, kernel_);
  // "auto": the treatment whose wall loads and wall-layer pressures match hydrostatics with this
  // wall model (measured, docs/boundary-pressure.md): MLS extrapolation where the walls are
  // samples (consistent holds its wall layer at ~1.5 x hydrostatic there and pushes a side wall
  // 3 % too hard), consistent for volume maps, where extrapolation would be mirroring.
  if (scene_.boundaryPressureAuto)
    scene_.boundaryPressure = boundaryModel_->implicit() ? BoundaryPressure::Consistent : BoundaryPressure::Extrapolation;
  // One virtual particle per fluid particle carries the whole wall within its support: a p_k
  // fitted from its one fluid neighbour is p_i (mirroring), and pushing with it twice over-pushes
  // near walls (measured, bench/wall_pressure.py: a resting tank's particle pressures 34-36 %
  // RMS off hydrostatic under DFSPH; under IISPH and WCSPH the tank blew up).
  if (boundaryModel_->implicit() && scene_.boundaryPressure != BoundaryPressure::Consistent)
    log_(LogLevel::Warning, std::string("simulation.boundaryPressure: \"") + boundaryPressureName(scene_.boundaryPressure) + "\" with " +
                                scene_.boundaryModel["type"].get<std::string>() +
                                " walls is p_k = p_i for the one virtual particle per fluid particle: wall-layer pressures are "
                                "far off hydrostatic and a tank filled to its walls blew up under IISPH and WCSPH "
                                "(docs/boundary-pressure.md); \"consistent\" (the \"auto\" choice) is the treatment for them");
  bodies_ = makeMovingBodies(scene_.boundaries, *boundaryModel_, scene_.particleRadius, fluid_->density0(), log_);
  if (bodies_) boundaryModel_->follow(bodies_->poses(false));  // the bodies' initial velocities
  PluginContext solverContext = context;
  solverContext.boundaryPressure = scene_.boundaryPressure;  // "auto" resolved above
  pressureSolver_ = plugins_.pressureSolvers.create(scene_.pressureSolver["type"].get<std::string>(), scene_.pressureSolver,
                                                    "simulation.pressureSolver", solverContext, log_);
  for (std::size_t i = 0; i < fd.forces.size(); ++i)
    forces_.push_back(plugins_.forces.create(fd.forces[i]["type"].get<std::string>(), fd.forces[i],
                                             fd.path + ".forces[" + std::to_string(i) + "]", context, log_));

  // Escape domain: the scene's, or the boundaries' bounding box with a margin.
  if (scene_.hasDomain) {
    hasDomain_ = true;
    domainMin_ = scene_.domainMin;
    domainMax_ = scene_.domainMax;
  } else if (std::any_of(scene_.boundaries.begin(), scene_.boundaries.end(),
                         [](const BoundaryObject& b) { return b.motion == BodyMotion::Static; })) {
    // Moving bodies do not count: they go where the fluid takes them.
    hasDomain_ = true;
    domainMin_ = Vector3r::Constant(std::numeric_limits<Real>::max());
    domainMax_ = -domainMin_;
    for (auto& b : scene_.boundaries) {
      if (b.motion != BodyMotion::Static) continue;
      Vector3r lo, hi;
      b.mesh.boundingBox(lo, hi);
      domainMin_ = domainMin_.cwiseMin(lo);
      domainMax_ = domainMax_.cwiseMax(hi);
    }
    const Vector3r margin = Real(0.05) * (domainMax_ - domainMin_) + Vector3r::Constant(kernel_.supportRadius());
    domainMin_ -= margin;
    domainMax_ += margin;
  }
  speedScale_ = sceneSpeedScale(scene_);
  checkStartInsideDomain();
  if (bodies_ && bodies_->hasDynamic()) guardBodies();
  chooseTimeStepCap();
  if (!scene_.probes.empty()) {
    probes_ = std::make_unique<Probes>(scene_.probes, scene_.boundaries, kernel_.supportRadius(), scene_.gravity);
    if (!scene_.output.enabled)
      log_(LogLevel::Info, "probes: output is off, so probes.csv is not written (the latest values are in the summary)");
  }
  dt_ = dtPrevious_ = scene_.initialTimeStep;
  // Every plugin has registered its fields by now: the frames' attributes must name some.
  checkAttributes(fluid_->fields(), scene_.output.attributes, "output.attributes");
  if (!scene_.restartFrom.empty()) restoreCheckpoint(scene_.restartFrom);
  if (scene_.output.checkpointInterval > 0 && !scene_.output.enabled)
    log_(LogLevel::Warning, "output.checkpointInterval: output is off, so no checkpoints are written");
  if (scene_.output.enabled) setOutputDirectory(scene_.output.directory);
}

Simulation::~Simulation() = default;

ResourceEstimate Simulation::estimateResources(Real endTime) const {
  ResourceEstimate e;
  const Real d = scene_.particleSpacing * scene_.particleRadius;
  for (const FluidBlock& b : scene_.fluids[0].blocks) {
    const auto n = blockCounts(b, d, scene_.particleRadius);
    e.fluidParticles += n[0] * n[1] * n[2];
  }
  e.fluidParticles += double(scene_.fluids[0].sourcePositions.size());
  for (const EmitterDescription& em : scene_.fluids[0].emitters) e.fluidParticles += Emitter::estimateCapacity(em, d, endTime);
  e.boundary = boundaryModel_->estimate(scene_.boundaries, kernel_);
  return e;
}

void Simulation::chooseTimeStepCap() {
  // The step the resolution calls for: the default cap's constant and the CFL condition at the
  // scene's speed scale, whatever step the user asks for. The implicit solvers remove a density
  // excess over this time (StepContext::densityRelaxationTime), so a shorter step taken by hand
  // converges to the same motion instead of kicking harder (the drift correction's velocity,
  // excess x h / time, grew as 1 / dt: a dam break's energy rose 20 % at dt = 0.14 ms, r = 0.01).
  // (cflFactor 1: the user's CFL factor is one of the step controls this must not follow).
  densityRelaxationTime_ = Real(kDefaultMaxTimeStep);
  if (speedScale_.speed > 0)
    densityRelaxationTime_ = std::min(densityRelaxationTime_, cflTimeStep(Real(1), speedScale_.speed));
  // A cap the user gave stands as it is.
  timeStepCap_ = scene_.maxTimeStep;
  if (scene_.maxTimeStepGiven) return;
  // The CFL condition at the fastest speed the scene will reach, not only at today's: a column
  // or a tank starts at rest (CFL: no bound), and its first steps at the constant cap (tuned
  // for r = 0.025) overshoot at fine resolution before any speed shows (issue 15: a 1 m column at
  // r = 0.006, a block filling its tank at r = 0.005 blew up). U: Simulation/SpeedScale.h.
  std::ostringstream why;
  why << "default maximum time step: min(" << scene_.maxTimeStep << " s";
  if (speedScale_.speed > 0) {
    const Real cfl = cflTimeStep(scene_.cflFactor, speedScale_.speed);
    timeStepCap_ = std::min(timeStepCap_, cfl);
    why << ", CFL at the speed scale " << speedScale_.speed << " m/s: " << cfl << " s";
  }
  // Explicit forces' own limits (Morris et al. 1997's viscous diffusion bound).
  for (std::size_t i = 0; i < forces_.size(); ++i) {
    const Real limit = forces_[i]->maxStableTimeStep(kernel_);
    if (limit < std::numeric_limits<Real>::infinity()) {
      timeStepCap_ = std::min(timeStepCap_, limit);
      why << ", " << scene_.fluids[0].forces[i]["type"].get<std::string>() << " stability: " << limit << " s";
    }
  }
  // An explicit pressure solver's own limit (WCSPH: the CFL condition on the speed of sound).
  const Real solverLimit = pressureSolver_->maxStableTimeStep(scene_.particleRadius, fluid_->density0());
  if (solverLimit < std::numeric_limits<Real>::infinity()) {
    timeStepCap_ = std::min(timeStepCap_, solverLimit);
    why << ", " << scene_.pressureSolver["type"].get<std::string>() << " stability: " << solverLimit << " s";
  }
  timeStepCap_ = std::max(timeStepCap_, scene_.minTimeStep);
  why << ") = " << timeStepCap_ << " s (simulation.maxTimeStep sets it by hand)";
  log_(LogLevel::Info, why.str());
}

namespace {
// "(x, y, z)", as the run's other messages write a point.
std::string pointText(const Vector3r& x) {
  std::ostringstream s;
  s << "(" << x[0] << ", " << x[1] << ", " << x[2] << ")";
  return s.str();
}
}  // namespace

void Simulation::checkStartInsideDomain() const {
  // What starts outside the domain would stop the first step as "leaked through a boundary or
  // blew up": the scene is wrong, not the run, so it is an input error naming the cause.
  if (!hasDomain_) return;
  const std::string domain = pointText(domainMin_) + " - " + pointText(domainMax_) +
                             (scene_.hasDomain ? "" : " (the static boundaries' box grown by 5 % and h; simulation.domain sets it)");
  const FluidModel& f = *fluid_;
  const auto outsideDomain = [&](const Vector3r& x) { return !insideBox(x, domainMin_, domainMax_); };
  const std::size_t outside = parallelSum<std::size_t>(f.size(), [&](std::size_t i) { return outsideDomain(f.positions[i]); });
  if (outside > 0)
    throw InputError(scene_.fluids[0].path + ": " + std::to_string(outside) + " of the fluid's " + std::to_string(f.size()) +
                     " particles start outside the domain " + domain + ", the first at " +
                     pointText(*std::find_if(f.positions.begin(), f.positions.end(), outsideDomain)));
  const auto& emitters = scene_.fluids[0].emitters;
  for (std::size_t e = 0; e < emitters.size(); ++e)
    if (outsideDomain(emitters[e].position))
      throw InputError(scene_.fluids[0].path + ".emitters[" + std::to_string(e) + "].position: " + pointText(emitters[e].position) +
                       " is outside the domain " + domain);
}

void Simulation::guardBodies() {
  // Where a body may go: the scene's domain, or the fluid's (the static objects' box) grown to
  // hold everything at t = 0 (a body dropped from above a floor slab starts outside the slab's box).
  bool has = hasDomain_;
  Vector3r lo = domainMin_, hi = domainMax_;
  if (hasDomain_ && !scene_.hasDomain) {
    auto add = [&](const Vector3r& x) {
      lo = lo.cwiseMin(x);
      hi = hi.cwiseMax(x);
    };
    for (const FluidBlock& b : scene_.fluids[0].blocks) add(b.min), add(b.max);
    for (const Vector3r& x : scene_.fluids[0].sourcePositions) add(x);
    for (const EmitterDescription& e : scene_.fluids[0].emitters) add(e.position);
    for (const BoundaryObject& o : scene_.boundaries)
      if (o.motion != BodyMotion::Static)
        for (const Vector3r& x : o.mesh.vertices) add(x);
    const Vector3r margin = Real(0.05) * (hi - lo) + Vector3r::Constant(kernel_.supportRadius());
    lo -= margin;
    hi += margin;
  }
  std::vector<std::string> labels;
  for (std::size_t i = 0; i < bodies_->count(); ++i) {
    const BoundaryObject& o = scene_.boundaries[bodies_->state(i).object];
    labels.push_back(o.name.empty() ? o.path : "'" + o.name + "' (" + o.path + ")");
  }
  const RigidBodyGuard::Limits limits = RigidBodyGuard::limitsFor(speedScale_.speed, has, lo, hi);
  // The guard would stop the first step on a body the scene's domain leaves out: an input error.
  for (std::size_t i = 0; i < bodies_->count(); ++i) {
    const MovingBodyState b = bodies_->state(i);
    if (b.motion == BodyMotion::Dynamic && has && !insideBox(b.x, lo, hi)) {
      throw InputError("simulation.domain: the dynamic body " + labels[i] + " starts outside it: its centre of mass is at " +
                       pointText(b.x) + ", the domain " + pointText(lo) + " - " + pointText(hi));
    }
  }
  bodyGuard_ = std::make_unique<RigidBodyGuard>(labels, limits);
  {
    std::ostringstream s;
    s << "dynamic bodies stop the run beyond " << limits.maxSpeed << " m/s (" << RigidBodyGuard::kSpeedFactor
      << " x the scene's speed scale " << speedScale_.speed << " m/s: fall height " << speedScale_.fallHeight
      << " m, initial speed " << speedScale_.initialSpeed << " m/s)";
    log_(LogLevel::Info, s.str());
  }
  // Bodies drawn into each other or into a wall: rigid contact pushes them apart at a bounded
  // speed (MovingBodies::maxPushOutSpeed); say so, since the scene is probably not what was meant.
  // Layers closer than half a particle radius count as touching (sample grids do not line up).
  for (const BodyOverlap& o : bodies_->overlaps(boundaryModel_->samples(), Real(0.5) * scene_.particleRadius)) {
    auto name = [&](Index object) {
      const BoundaryObject& b = scene_.boundaries[object];
      return b.name.empty() ? b.path : "'" + b.name + "' (" + b.path + ")";
    };
    std::ostringstream s;
    s << name(o.objectA) << " and " << name(o.objectB) << " overlap by " << o.depth
      << " m at t = 0: rigid contact pushes them apart at most " << bodies_->maxPushOutSpeed() << " m/s";
    log_(LogLevel::Warning, s.str());
  }
}

void Simulation::initializeFluid() {
  // Blocks are filled on a cubic lattice of spacing d = particleSpacing r, one particle per cell
  // of volume d^3. The default d = 0.8^(1/3) 2r gives SPlisHSPlasH's particle volume 0.8 (2r)^3
  // and its settled neighbour count (~38), but the block starts at rest density instead of 20 %
  // under-dense. (With d = 2r, ~27 neighbours, the SPH density over-estimates a disordered
  // fluid's mass density and a resting column's pressure gradient reads ~5 % low.) A block on
  // one of SPlisHSPlasH's lattices (an imported scene) keeps the mass rho0 d^3 per particle, and
  // so SPlisHSPlasH's start.
  const Real r = scene_.particleRadius, d = scene_.particleSpacing * r;
  std::vector<Vector3r> x, v;
  for (const FluidBlock& b : scene_.fluids[0].blocks) {
    // Counted in floating point; refuseIfTooLarge has bounded their product by 2^32.
    sampleBlock(b, d, r, x);
    v.resize(x.size(), b.velocity);
  }
  // Particles from point files and mesh volumes, sampled when the scene was read.
  const FluidDescription& fd = scene_.fluids[0];
  x.insert(x.end(), fd.sourcePositions.begin(), fd.sourcePositions.end());
  v.insert(v.end(), fd.sourceVelocities.begin(), fd.sourceVelocities.end());
  FluidModel& f = *fluid_;
  // Emitters' budgets up front: no field reallocates later, so data pointers never move.
  if (!emitters_.empty()) {
    std::size_t budget = x.size();
    for (const Emitter& e : emitters_) budget += e.capacity();
    f.fields().reserve(budget);
  }
  f.resize(x.size());
  nextId_ = Index(x.size());
  const Real mass = f.density0() * d * d * d;
  for (std::size_t i = 0; i < x.size(); ++i) {
    f.positions[i] = x[i];
    f.velocities[i] = v[i];
    f.masses[i] = mass;
    f.ids[i] = Index(i);
  }
}

void Simulation::dropParticlesInsideBodies() {
  // Fluid inside a closed object (a block filled through a body) could never get out through
  // its sampled surface: drop it. Particles overlapping the surface are pushed out by the
  // solver (DFSPH overlapReliefSpeed).
  FluidModel& f = *fluid_;
  std::vector<char> inside(f.size(), 0);
  for (const BoundaryObject& o : scene_.boundaries) {
    if (o.inverted) continue;
    Vector3r lo, hi;
    o.mesh.boundingBox(lo, hi);
    // The hierarchy's winding number: O(log n) per particle instead of every triangle.
    const TriangleBvh surface = o.isBox ? TriangleBvh(TriangleMesh()) : TriangleBvh(o.mesh);
    parallelForDynamic(f.size(), [&](std::size_t i) {
      const Vector3r& x = f.positions[i];
      if (!insideBox(x, lo, hi)) return;
      if (o.isBox || surface.windingNumber(x) > Real(0.5)) inside[i] = 1;
    });
  }
  std::vector<Index> keep;
  for (std::size_t i = 0; i < f.size(); ++i)
    if (!inside[i]) keep.push_back(Index(i));
  if (keep.size() == f.size()) return;
  stats_.particlesDroppedInsideBodies = f.size() - keep.size();
  f.fields().compact(keep);
  log_(LogLevel::Info, std::to_string(stats_.particlesDroppedInsideBodies) + " fluid particles inside boundary objects dropped at start-up");
}

void Simulation::emitParticles() {
  for (Emitter& e : emitters_) stats_.particlesEmitted += e.emit(*fluid_, time_, dt_, nextId_);
}

void Simulation::coupleRigidBodies(StepContext& ctx) {
  // Eq. (35): the reaction of the solver's boundary term on every sample of a moving body
  // (pairImpulses_, from measureWallLoads), summed into force and torque per body; then the
  // bodies move, and the boundary model moves its samples to their new poses. Animated bodies
  // are not moved by the fluid, but their fluid force is reported too.
  bodies_->takeFluidImpulses(boundaryNeighbors_, fluid_->positions, boundaryModel_->samples(), pairImpulses_);
  bodies_->advance(dt_, scene_.gravity, boundaryModel_->samples(), fluid_->positions, fluid_->masses, fluid_->velocities);
  boundaryModel_->follow(bodies_->poses(true));
}

void Simulation::measureWallLoads(StepContext& ctx) {
  pressureSolver_->boundaryImpulses(ctx, pairImpulses_);
  if (!probes_ || !probes_->readsLoads()) return;
  // Torques about the moving bodies' centres of mass where they are during this step.
  if (bodies_)
    for (std::size_t i = 0; i < bodies_->count(); ++i) {
      const MovingBodyState b = bodies_->state(i);
      probes_->setObjectCentre(b.object, b.x);
    }
  probes_->measureLoads(boundaryNeighbors_, fluid_->positions, *boundaryModel_, pairImpulses_, dt_);
}

void Simulation::removeParticlesOutside() {
  const FluidDescription& fd = scene_.fluids[0];
  FluidModel& f = *fluid_;
  std::vector<Index> keep;
  keep.reserve(f.size());
  for (std::size_t i = 0; i < f.size(); ++i) {
    const Vector3r& x = f.positions[i];
    if (insideBox(x, fd.removeMin, fd.removeMax)) keep.push_back(Index(i));
  }
  if (keep.size() == f.size()) return;
  stats_.particlesRemoved += f.size() - keep.size();
  f.fields().compact(keep);
}

StepContext Simulation::makeContext() {
  return StepContext{*fluid_,          boundaryModel_->samples(), fluidNeighbors_, paddedFluidNeighbors_, boundaryNeighbors_,
                     kernel_,          scene_.gravity,            scene_.particleRadius,
                     dt_,              dtPrevious_,               densityRelaxationTime_, time_,
                     stats_.steps,     log_,                      bodies_ && bodies_->hasFreeDynamic() ? bodies_.get() : nullptr,
                     boundaryModel_->implicit()};
}

void Simulation::step() {
  if (stats_.steps == 0 && writer_) writeFrameIfDue();  // frame 0: the initial state
  Timer stepTimer;

  // Emitters: new layers of particles leave their nozzles.
  if (!emitters_.empty()) {
    ScopedTimer t(stats_.emission);
    emitParticles();
  }
  // Neighbours: once per step, reused by every loop below.
  {
    ScopedTimer t(stats_.neighbourSearch);
    findNeighbors();
  }
  // Densities, Eq. (14).
  {
    ScopedTimer t(stats_.densities);
    computeDensities();
  }
  // The plugins' view of this step's particles: made after the emitters and the neighbour search,
  // which are what resize the fluid's fields and a volume map's virtual samples.
  StepContext ctx = makeContext();
  // DFSPH's divergence solve (no-op for other solvers).
  {
    ScopedTimer t(stats_.divergenceSolve);
    pressureSolver_->beforeNonPressureForces(ctx);
  }
  // Non-pressure forces in scene order.
  {
    ScopedTimer t(stats_.nonPressureForces);
    computeNonPressureAccelerations(ctx);
  }
  // Adaptive time step (CFL), then v* = v + dt a^np, Eq. (4).
  updateTimeStep();
  ctx.dt = dt_;
  {
    FluidModel& f = *fluid_;
    parallelFor(f.size(), [&](std::size_t i) { f.velocities[i] += dt_ * f.accelerations[i]; });
  }
  // Pressure solve: v* -> v(t + dt).
  {
    ScopedTimer t(stats_.pressureSolve);
    pressureSolver_->solve(ctx);
  }
  const PressureSolverStats& ps = pressureSolver_->stats();
  lastPressureIterations_ = ps.pressureIterations;
  stats_.pressureIterations += ps.pressureIterations;
  stats_.divergenceIterations += ps.divergenceIterations;
  // Wall loads: the solver's reaction on every boundary sample, for the bodies and the probes.
  if (bodies_ || (probes_ && probes_->readsLoads())) {
    ScopedTimer t(bodies_ ? stats_.rigidBodies : stats_.probes);
    measureWallLoads(ctx);
  }
  // Rigid-body coupling: fluid impulses move the bodies (Eq. 35), the bodies move their samples.
  if (bodies_) {
    ScopedTimer t(stats_.rigidBodies);
    coupleRigidBodies(ctx);
  }
  // Integration: x(t + dt) = x(t) + dt v(t + dt); then particles that left the removal box go.
  {
    ScopedTimer t(stats_.integration);
    integrate();
    if (scene_.fluids[0].removeOutside) removeParticlesOutside();
  }
  dtPrevious_ = dt_;
  time_ += dt_;
  ++stats_.steps;
  if (ps.hitIterationCap) {
    ++stats_.iterationCapHits;
    ++stats_.consecutiveCapHits;
    if (stats_.iterationCapHits <= 5 || stats_.iterationCapHits % 100 == 0)
      log_(LogLevel::Warning, "step " + std::to_string(stats_.steps) + ", t = " + std::to_string(time_) +
                                  " s: pressure solver hit its iteration cap (density error " +
                                  std::to_string(100 * ps.densityError) + " %)");
  } else {
    stats_.consecutiveCapHits = 0;
  }
  checkState();
  if (probes_) {
    ScopedTimer t(stats_.probes);
    probes_->measureLevels(*fluid_, kernel_);
    writeProbeRowIfDue();
  }
  stats_.wallSeconds += stepTimer.seconds();
  if (writer_) {
    ScopedTimer t(stats_.exportTime);
    writeFrameIfDue();
    writeCheckpointIfDue();
  }
}

void Simulation::extendRunTo(double until) {
  if (emitters_.empty() || !(until > emittersEndTime_)) return;
  refuseIfTooLarge(estimateResources(until), scene_.maxParticles);
  emittersEndTime_ = until;
  std::size_t budget = fluid_->size();
  for (Emitter& e : emitters_) {
    e.extendTo(until);
    budget += e.remaining();
  }
  fluid_->fields().reserve(std::max(budget, fluid_->fields().capacity()));
}

void Simulation::run(double until, const std::function<void(const Simulation&)>& progress, const std::function<bool()>& stop) {
  extendRunTo(until);
  while (!reached(until) && !(stop && stop())) {
    step();
    if (progress) progress(*this);
  }
}

void Simulation::findNeighbors() {
  FluidModel& f = *fluid_;
  // Z-order sort every sortInterval steps: neighbours in space become neighbours in memory.
  if (scene_.sortInterval > 0 && stats_.steps % std::size_t(scene_.sortInterval) == 0) {
    const auto order = zOrderPermutation(f.positions.data(), f.size(), kernel_.supportRadius());
    f.fields().permuteSorted(order);
  }
  fluidGrid_.build(f.positions.data(), f.size(), kernel_.supportRadius());
  // The fluid part of the densities comes with the lists (computeDensities).
  buildNeighborLists(fluidGrid_, f.positions.data(), f.size(), kernel_, true, PairGradients::Factors, fluidNeighbors_, f.masses.data());
  // The padded copy only where a plugin of the scene reads it (2 % of DamBreak's step).
  bool padded = pressureSolver_->readsPaddedNeighbors();
  for (const auto& force : forces_) padded = padded || force->readsPaddedNeighbors();
  if (padded) paddedFluidNeighbors_.build(fluidNeighbors_);
  boundaryModel_->findNeighbors(f, kernel_, boundaryNeighbors_, fluidNeighbors_.kernelSums.data());
}

void Simulation::computeDensities() {
  FluidModel& f = *fluid_;
  const BoundarySamples& b = boundaryModel_->samples();
  const Real rho0 = f.density0();
  struct DensityError {
    double sum = 0, max = 0;
  };
  auto join = [](DensityError& into, const DensityError& from) {
    into.sum += from.sum;
    into.max = std::max(into.max, from.max);
  };
  const bool boundarySummed = boundaryNeighbors_.kernelSums.size() == f.size();
  const DensityError error = parallelReduce(f.size(), DensityError{}, join, [&](std::size_t i, DensityError& acc) {
    const Vector3r xi = f.positions[i];
    // m_i W(0) + sum_j m_j W_ij, summed by the neighbour search (findNeighbors), then the
    // boundary's sum_k m~_k W_ik: by the boundary's search where its model summed it there.
    Real rho;
    if (boundarySummed) {
      rho = boundaryNeighbors_.kernelSums[i];
    } else {
      rho = fluidNeighbors_.kernelSums[i];
      for (Index e = boundaryNeighbors_.begin(i); e < boundaryNeighbors_.end(i); ++e) {
        const Index k = boundaryNeighbors_.indices[e];
        rho += b.masses[k] * kernel_.W(xi - b.positions[k]);
      }
    }
    f.densities[i] = rho;
    const double err = std::max<double>(rho - rho0, 0) / rho0;  // compression only
    acc.sum += err;
    acc.max = std::max(acc.max, err);
  });
  // The density error of the state the last step produced (step 0 is the initial state).
  if (stats_.steps > 0 && f.size() > 0) {
    const double avg = error.sum / double(f.size());
    stats_.densityErrorSum += avg;
    stats_.densityErrorMax = std::max(stats_.densityErrorMax, avg);
    ++stats_.densityErrorSamples;
  }
}

void Simulation::computeNonPressureAccelerations(StepContext& ctx) {
  FluidModel& f = *fluid_;
  const Vector3r g = scene_.gravity;
  parallelFor(f.size(), [&](std::size_t i) { f.accelerations[i] = g; });
  for (auto& force : forces_) force->addAccelerations(ctx);
}

void Simulation::updateTimeStep() {
  // CFL: dt = cflFactor 0.4 (2r) / max |v + dt a|, clamped to [minTimeStep, timeStepCap_]
  // (maxTimeStep when given, else chooseTimeStepCap's bound).
  FluidModel& f = *fluid_;
  const Real dtOld = dt_;
  const Real maxSpeed2 =
      parallelMax(f.size(), Real(0), [&](std::size_t i) { return (f.velocities[i] + dtOld * f.accelerations[i]).squaredNorm(); });
  Real dt = timeStepCap_;
  if (maxSpeed2 > 0) dt = cflTimeStep(scene_.cflFactor, std::sqrt(maxSpeed2));
  // timeStepControl "iterations" (SPlisHSPlasH's cflMethod 2): a solve that needed many
  // iterations says the step is too long for the pressure to settle within it, whatever the
  // speeds say; the step then shrinks 10 % per step until the solves are cheap again, and grows
  // back by 10 % per step, never beyond the CFL step. A solver without iterations (WCSPH: 0)
  // keeps the CFL step.
  if (scene_.iterationFeedback && lastPressureIterations_ > 0) {
    const Real factor = lastPressureIterations_ > 10 ? Real(0.9) : lastPressureIterations_ < 5 ? Real(1.1) : Real(1);
    dt = std::min(dt, factor * dtOld);
  }
  // Explicit forces' local stability bounds for the particles they just saw (a viscosity at a
  // free surface), like the CFL condition under a cap the user gave as well.
  bool forceLimited = false;
  for (const auto& force : forces_) {
    const Real limit = force->stepLimit();
    if (limit < dt && limit < timeStepCap_) dt = limit, forceLimited = true;
  }
  if (forceLimited) ++stats_.stabilityLimitedSteps;
  // The boundary's bound (volume maps' approachTolerance): a particle moving into a wall or corner.
  const Real boundaryLimit = boundaryModel_->approachStepLimit(*fluid_, boundaryNeighbors_, kernel_, std::min(dt, timeStepCap_));
  if (boundaryLimit < dt && boundaryLimit < timeStepCap_) dt = boundaryLimit, ++stats_.boundaryLimitedSteps;
  dt_ = std::clamp(dt, scene_.minTimeStep, timeStepCap_);
}

void Simulation::integrate() {
  FluidModel& f = *fluid_;
  parallelFor(f.size(), [&](std::size_t i) { f.positions[i] += dt_ * f.velocities[i]; });
}

void Simulation::checkState() {
  // Bodies first: a body gone non-finite or runaway passes it on to the fluid within its step
  // (iterated coupling moves its samples during the solve), and the body is then the cause to name.
  if (bodyGuard_) bodyGuard_->check(*bodies_, stats_.steps, time_);
  FluidModel& f = *fluid_;
  const std::ptrdiff_t n = std::ptrdiff_t(f.size());
  // The first particle that is non-finite, and the first outside the domain (n: none).
  using FirstBadOut = std::pair<std::ptrdiff_t, std::ptrdiff_t>;
  auto join = [](FirstBadOut& into, const FirstBadOut& from) {
    into.first = std::min(into.first, from.first);
    into.second = std::min(into.second, from.second);
  };
  const auto [firstBad, firstOut] = parallelReduce(std::size_t(n), FirstBadOut{n, n}, join, [&](std::size_t i, FirstBadOut& first) {
    const Vector3r& x = f.positions[i];
    if (!x.allFinite() || !f.velocities[i].allFinite() || !std::isfinite(f.pressures[i]))
      first.first = std::min(first.first, std::ptrdiff_t(i));
    else if (hasDomain_ && !insideBox(x, domainMin_, domainMax_))
      first.second = std::min(first.second, std::ptrdiff_t(i));
  });
  auto where = [&](std::ptrdiff_t i) {
    std::ostringstream s;
    s << "step " << stats_.steps << ", t = " << time_ << " s: particle " << i << " (id " << f.ids[i] << ")";
    return s.str();
  };
  if (firstBad < n) throw SimulationError(where(firstBad) + " has a non-finite position, velocity or pressure (NaN/inf): the simulation blew up");
  if (firstOut < n)
    throw SimulationError(where(firstOut) + " left the domain at " + pointText(f.positions[firstOut]) +
                          ": it leaked through a boundary or the simulation blew up");
  if (stats_.consecutiveCapHits >= std::size_t(scene_.iterationCapSteps)) {
    std::ostringstream s;
    s << "step " << stats_.steps << ", t = " << time_ << " s: the pressure solver hit its iteration cap in "
      << stats_.consecutiveCapHits << " steps in a row: the simulation diverges (lower the time step or raise maxIterations)";
    throw SimulationError(s.str());
  }
}

void Simulation::setOutputDirectory(const std::string& dir) {
  // A folder this simulation writes already is its own; any other must hold no other run's files.
  if (dir != ownedDirectory_) {
    // A restarted run continues its own frames: the folder's earlier files are its own.
    if (restarted_ && !scene_.output.overwrite) {
      std::error_code ec;
      std::filesystem::create_directories(dir, ec);
      if (ec) throw OutputError("cannot create output folder '" + dir + "': " + ec.message());
    } else {
      claimOutputFolder(dir, scene_.output.overwrite);
    }
    ownedDirectory_ = dir;
    // The scene as run (after --set and Python overrides) beside the frames.
    writeFileAtomically((std::filesystem::path(dir) / "scene.resolved.json").string(), scene_.raw.dump(2) + "\n");
  }
  scene_.output.directory = dir;
  scene_.output.enabled = true;
  const OutputSettings& o = scene_.output;
  writer_ = std::make_unique<FrameSeries>(dir, fluid_->name(), o.format, o.precision);
  if (bodies_) {
    bodyWriter_ = std::make_unique<FrameSeries>(dir, "bodies", o.format, o.precision);
    if (bodyCsv_.empty()) bodyCsv_ = bodies_->csvHeader();
  }
  // The boundary once, for context in ParaView.
  const BoundarySamples& b = boundaryModel_->samples();
  if (!boundaryModel_->implicit() && b.size() > 0) {
    VtuPointCloud cloud(b.positions.data(), b.size());
    cloud.add("mass", b.masses.data(), 1);
    cloud.add("body", b.bodies.data());
    writeFileAtomically((std::filesystem::path(dir) / "boundary.vtu").string(), cloud.serialize());
  } else if (boundaryModel_->implicit() && !scene_.boundaries.empty()) {
    // An implicit model (volume maps) has no fixed samples: the static objects' surfaces instead
    // (moving bodies are in the bodies series).
    TriangleMesh all;
    std::vector<Index> body;
    for (std::size_t o = 0; o < scene_.boundaries.size(); ++o) {
      if (scene_.boundaries[o].motion != BodyMotion::Static) continue;
      const TriangleMesh& mesh = scene_.boundaries[o].mesh;
      const Index base = Index(all.vertices.size());
      all.vertices.insert(all.vertices.end(), mesh.vertices.begin(), mesh.vertices.end());
      body.insert(body.end(), mesh.vertices.size(), Index(o));
      for (const auto& t : mesh.triangles) all.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    }
    VtuPointCloud cloud(all.vertices.data(), all.vertices.size());
    cloud.setTriangles(all.triangles.data(), all.triangles.size());
    cloud.add("body", body.data());
    writeFileAtomically((std::filesystem::path(dir) / "boundary.vtu").string(), cloud.serialize());
  }
  nextFrame_ = std::size_t(std::ceil(time_ * scene_.output.fps - Real(1e-6)));
  const bool continuing = resumed_.pending && dir == resumed_.directory;
  if (continuing) {
    // The restarted run's series go on where the checkpoint left them (frame numbers, .pvd, bodies.csv).
    resumed_.pending = false;
    writer_->setFrames(resumed_.frames);
    if (bodyWriter_) bodyWriter_->setFrames(resumed_.bodyFrames), bodyCsv_ = resumed_.bodyCsv;
    nextFrame_ = resumed_.nextFrame;
  }
  if (probes_) {
    std::string header = "time";
    for (const std::string& c : probes_->columns()) header += "," + c;
    const std::string path = (std::filesystem::path(dir) / "probes.csv").string();
    // A restarted run keeps the rows up to its checkpoint, as its frame series do; rows the
    // first run wrote after it (before it was killed) are dropped, since this run writes them anew.
    const std::string kept = continuing ? probeRowsUpTo(path, header, time_) : header;
    probeFile_ = std::make_unique<LineFile>(path, kept);
    // A restarted run's next row and the loads since its last one are the checkpoint's (the row
    // due at the checkpoint's time was written before it); a new file starts at the next row due.
    if (!continuing) {
      nextProbeRow_ = scene_.output.probeFps > 0 ? std::size_t(std::ceil(time_ * scene_.output.probeFps - Real(1e-6))) : 0;
      probes_->startWindow();
    }
  }
}

void Simulation::setOutputEnabled(bool enabled) {
  if (!enabled) writer_.reset(), bodyWriter_.reset(), probeFile_.reset();
  else if (!writer_) setOutputDirectory(scene_.output.directory);
  scene_.output.enabled = enabled;
}

void Simulation::setOutputFps(Real fps) {
  scene_.output.fps = fps;
  nextFrame_ = std::size_t(std::ceil(time_ * fps - Real(1e-6)));
}

void Simulation::writeFrameIfDue() {
  // A frame is due once the simulated time reaches index / fps (within half a step).
  if (time_ + Real(0.5) * dt_ < Real(nextFrame_) / scene_.output.fps) return;
  updatePressureField();
  const OutputSettings& o = scene_.output;
  writer_->write(nextFrame_, time_, particleTable(fluid_->fields(), fluid_->size(), o.attributes, o.format));
  if (bodyWriter_) {
    // The bodies (surfaces or poses) as a second series, and their state as one CSV row per body.
    bodyWriter_->write(nextFrame_, time_, BodyFrame(*bodies_, o.bodies, o.format).table());
    bodyCsv_ += bodies_->csvRows(time_);
    writeFileAtomically((std::filesystem::path(scene_.output.directory) / "bodies.csv").string(), bodyCsv_);
  }
  ++nextFrame_;
}

void Simulation::writeProbeRowIfDue() {
  // Every step, or once the simulated time reaches index / probeFps (within half a step).
  if (!probeFile_) return;
  const Real fps = scene_.output.probeFps;
  if (fps > 0) {
    if (time_ + Real(0.5) * dt_ < Real(nextProbeRow_) / fps) return;
    ++nextProbeRow_;
  }
  char number[32];
  std::snprintf(number, sizeof(number), "%.9g", double(time_));
  std::string row = number;
  for (double v : probes_->windowValues()) {
    std::snprintf(number, sizeof(number), ",%.9g", v);
    row += number;
  }
  probes_->startWindow();
  probeFile_->append(row);
}

std::string Simulation::probeRowsUpTo(const std::string& path, const std::string& header, double time) {
  std::ifstream in(path);
  std::string line, kept = header;
  if (!in || !std::getline(in, line) || line != header) return header;  // none, or another scene's columns
  // Rows carry their time as "%.9g" (writeProbeRowIfDue): compare with `time` printed the same way.
  char number[32];
  std::snprintf(number, sizeof(number), "%.9g", double(time));
  const double last = std::strtod(number, nullptr);
  while (std::getline(in, line)) {
    if (line.empty() || !(std::strtod(line.c_str(), nullptr) <= last)) break;
    kept += "\n" + line;
  }
  return kept;
}

void Simulation::updatePressureField() {
  // The SPH estimate of the pressure field at each particle, the kernel (Shepard) average of the
  // solver's pressures over its fluid neighbourhood, sum_j V_j p_j W_ij / sum_j V_j W_ij (j = i
  // included). The solver's per-particle value is the multiplier that holds rho_i = rho0 in the
  // particles' disordered packing; it scatters about rho0 g (one spacing) around the field
  // at every depth, frozen in place (a 20-layer resting tank: 5.2 % RMS of rho0 g H per
  // particle, 4.9 % after averaging each particle over 0.5 s; its kernel average 1.2 %, the wall
  // layers within 2 %: docs/boundary-pressure.md). Its sum over the walls is what the probes
  // read (from the solver's impulses, not from this field). Computed on demand (frames, Python)
  // with the neighbours of the particles where they are now (the step's lists are from before
  // integration, and emitters and removal change the particles); the next step searches again.
  if (pressureFieldStep_ == stats_.steps && pressureField_->size() == fluid_->size()) return;
  FluidModel& f = *fluid_;
  std::vector<Real>& out = *pressureField_;
  fluidGrid_.build(f.positions.data(), f.size(), kernel_.supportRadius());
  buildNeighborLists(fluidGrid_, f.positions.data(), f.size(), kernel_, true, PairGradients::Factors, fluidNeighbors_);
  parallelFor(f.size(), [&](std::size_t i) {
    const Vector3r xi = f.positions[i];
    const Real selfWeight = f.masses[i] / f.densities[i] * kernel_.W0();
    Real weight = selfWeight, sum = selfWeight * f.pressures[i];
    for (Index e = fluidNeighbors_.begin(i); e < fluidNeighbors_.end(i); ++e) {
      const Index j = fluidNeighbors_.indices[e];
      const Real w = f.masses[j] / f.densities[j] * kernel_.W(xi - f.positions[j]);
      weight += w;
      sum += w * f.pressures[j];
    }
    out[i] = sum / weight;
  });
  pressureFieldStep_ = stats_.steps;
}

void Simulation::exportFrame(const std::string& path) {
  bool compressed = false;
  const FrameFormat format = frameFormatOfPath(path, compressed);
  const FramePrecision precision = sizeof(Real) == 8 ? FramePrecision::Double : FramePrecision::Float;
  updatePressureField();
  writeFileAtomically(path, serializeFrame(particleTable(fluid_->fields(), fluid_->size(), scene_.output.attributes, format), format,
                                           precision, compressed));
}

void Simulation::addForce(std::unique_ptr<NonPressureForce> force) {
  // An added explicit force's own limit bounds the default cap too (a given maxTimeStep stands).
  if (!scene_.maxTimeStepGiven) timeStepCap_ = std::max(std::min(timeStepCap_, force->maxStableTimeStep(kernel_)), scene_.minTimeStep);
  forces_.push_back(std::move(force));
}

std::size_t Simulation::particlesLost() const {
  return countParticlesInsideSolids(scene_.boundaries, fluid_->positions, scene_.particleRadius);
}

json Simulation::summary() const {
  const auto& s = stats_;
  const double steps = double(std::max<std::size_t>(s.steps, 1));
  const double errSamples = double(std::max<std::size_t>(s.densityErrorSamples, 1));
  return {
      {"scene", scene_.raw.value("name", std::string())},
      {"fluidParticles", fluid_->size()},
      {"boundaryParticles", boundaryModel_->samples().size()},
      {"steps", s.steps},
      {"simulatedTime", time_},
      {"wallSeconds", s.wallSeconds},
      {"threads", omp_get_max_threads()},
      {"precision", precisionName()},
      {"pressureSolver", scene_.pressureSolver["type"]},
      {"boundaryPressure", boundaryPressureName(scene_.boundaryPressure)},
      {"averagePressureIterations", double(s.pressureIterations) / steps},
      {"averageDivergenceIterations", double(s.divergenceIterations) / steps},
      {"averageDensityErrorPercent", 100.0 * s.densityErrorSum / errSamples},
      {"maxDensityErrorPercent", 100.0 * s.densityErrorMax},
      {"iterationCapHits", s.iterationCapHits},
      {"stabilityLimitedSteps", s.stabilityLimitedSteps},
      {"boundaryLimitedSteps", s.boundaryLimitedSteps},
      {"maxTimeStep", timeStepCap_},
      {"particlesLost", particlesLost()},
      {"particlesEmitted", s.particlesEmitted},
      {"particlesRemoved", s.particlesRemoved},
      {"particlesDroppedInsideBodies", s.particlesDroppedInsideBodies},
      {"movingBodies", bodies_ ? bodies_->count() : 0},
      {"msPerStep", 1000.0 * s.wallSeconds / steps},
      {"usPerParticleStep", 1e6 * s.wallSeconds / steps / double(std::max<std::size_t>(fluid_->size(), 1))},
      {"phaseSeconds",
       {{"neighbourSearch", s.neighbourSearch},
        {"densities", s.densities},
        {"divergenceSolve", s.divergenceSolve},
        {"nonPressureForces", s.nonPressureForces},
        {"pressureSolve", s.pressureSolve},
        {"integration", s.integration},
        {"rigidBodies", s.rigidBodies},
        {"emission", s.emission},
        {"probes", s.probes},
        {"export", s.exportTime}}},
      {"probes", probes_ ? probes_->latest() : json::object()},
  };
}

std::unique_ptr<Simulation> loadSimulation(const std::string& scenePath,
                                           const std::vector<std::pair<std::string, std::string>>& overrides, LogSink log,
                                           const PluginRegistry& plugins) {
  SceneDescription scene = loadSceneFile(scenePath, overrides, log);
  return namingSceneFile(scenePath, [&] { return std::make_unique<Simulation>(std::move(scene), plugins, std::move(log)); });
}

}  // namespace consph
