// Simulation's checkpoints: the state file that lets a stopped run continue bit for bit
// (Simulation::saveCheckpoint / restoreCheckpoint, written every output.checkpointInterval).
// Blocks (Utilities/StateArchive.h): the build's precision, the scene (without output.* and
// simulation.stopAt, which a restart may change), time and time-step state, step statistics,
// counters, every particle field by name, each body's state and each emitter's.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "Simulation/FrameSeries.h"
#include "Simulation/Simulation.h"
#include "Utilities/StateArchive.h"
#include "Utilities/VtkWriter.h"

namespace consph {

namespace {
// What must match between the checkpoint's scene and the restarted one.
json comparableScene(json scene) {
  scene.erase("output");
  if (scene.contains("simulation") && scene["simulation"].is_object()) scene["simulation"].erase("stopAt");
  return scene;
}

// The first difference between two scenes, as "PATH (checkpoint: A, scene: B)".
std::string firstDifference(const json& saved, const json& current) {
  const json patch = json::diff(saved, current);
  if (patch.empty()) return "";
  const json& op = patch[0];
  const std::string path = op["path"].get<std::string>();
  const json::json_pointer pointer(path);
  const std::string was = saved.contains(pointer) ? saved.at(pointer).dump() : "(absent)";
  const std::string now = current.contains(pointer) ? current.at(pointer).dump() : "(absent)";
  return path + " (checkpoint: " + was + ", scene: " + now + ")";
}

// Frame lists as text: one "TIME FILE" line each (times with 17 digits: they round-trip).
std::string framesText(const std::vector<std::pair<double, std::string>>& frames) {
  std::ostringstream s;
  s.precision(17);
  for (auto& [t, f] : frames) s << t << " " << f << "\n";
  return s.str();
}
std::vector<std::pair<double, std::string>> framesFromText(const std::string& text) {
  std::vector<std::pair<double, std::string>> frames;
  std::istringstream s(text);
  double t;
  std::string f;
  while (s >> t >> f) frames.emplace_back(t, f);
  return frames;
}

// One body's state as plain numbers (Eigen types are not trivially copyable): x, v, w, fluid
// force, fluid torque (3 each), q (w x y z).
struct BodyState {
  Real values[19];
};
BodyState stateOf(const MovingBodyState& b) {
  BodyState s;
  Real* p = s.values;
  for (const Vector3r* v : {&b.x, &b.v, &b.w, &b.fluidForce, &b.fluidTorque})
    for (int k = 0; k < 3; ++k) *p++ = (*v)[k];
  for (Real c : {b.q.w(), b.q.x(), b.q.y(), b.q.z()}) *p++ = c;
  return s;
}
void setState(MovingBodyState& b, const BodyState& s) {
  const Real* p = s.values;
  for (Vector3r* v : {&b.x, &b.v, &b.w, &b.fluidForce, &b.fluidTorque})
    for (int k = 0; k < 3; ++k) (*v)[k] = *p++;
  b.q = Quaternionr(p[0], p[1], p[2], p[3]);
}
}  // namespace

void Simulation::saveCheckpoint(const std::string& path) const {
  StateWriter out;
  out.putString("precision", precisionName());
  out.putString("scene", comparableScene(scene_.raw).dump());
  out.put("time", time_);
  out.put("dt", dt_);
  out.put("dtPrevious", dtPrevious_);
  out.put("timeStepCap", timeStepCap_);
  out.put("lastPressureIterations", lastPressureIterations_);
  out.put("stats", stats_);
  out.put("nextId", nextId_);
  out.put("emittersEndTime", emittersEndTime_);
  out.put("nextFrame", nextFrame_);
  out.put("nextProbeRow", nextProbeRow_);
  if (probes_) {  // the loads since the last probes.csv row (Probes::windowValues)
    out.putVector("probeWindow/impulses", probes_->window().impulses);
    out.put("probeWindow/time", probes_->window().time);
    out.put("probeWindow/steps", probes_->window().steps);
  }
  out.put("nextCheckpoint", nextCheckpoint_);
  out.put("checkpointsWritten", checkpointsWritten_);
  // Particle fields: every one, in registration order, with its type; plugins keep what must
  // survive a step (warm starts) in fields, so this is their state too.
  ParticleFields& fields = fluid_->fields();
  out.put("particles", fluid_->size());
  out.put("capacity", fields.capacity());
  std::string names;
  for (auto& f : fields.all()) {
    names += f->name() + "\n";
    out.put("fieldType/" + f->name(), int(f->type()));
    const std::size_t valueBytes = f->type() == FieldType::Index ? sizeof(Index) : std::size_t(f->components()) * sizeof(Real);
    out.putBytes("field/" + f->name(), f->data(), fluid_->size() * valueBytes);
  }
  out.putString("fields", names);
  std::vector<BodyState> bodies;
  if (bodies_)
    for (std::size_t i = 0; i < bodies_->count(); ++i) bodies.push_back(stateOf(bodies_->state(i)));
  out.putVector("bodies", bodies);
  std::vector<Emitter::State> emitters;
  for (const Emitter& e : emitters_) emitters.push_back(e.state());
  out.putVector("emitters", emitters);
  // Output series, so that a run restarted into the same folder continues its .pvd and bodies.csv.
  out.putString("output/directory", scene_.output.enabled ? scene_.output.directory : "");
  out.putString("output/frames", writer_ ? framesText(writer_->frames()) : "");
  out.putString("output/bodyFrames", bodyWriter_ ? framesText(bodyWriter_->frames()) : "");
  out.putString("output/bodyCsv", bodyCsv_);
  writeFileAtomically(path, out.bytes());
}

void Simulation::restoreCheckpoint(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw InputError("--restart: cannot read checkpoint '" + path + "'");
  std::stringstream buffer;
  buffer << file.rdbuf();
  const StateReader in(buffer.str(), path);
  auto refuse = [&](const std::string& why) { throw InputError(path + ": cannot restart: " + why); };
  if (in.bytes("precision") != precisionName())
    refuse("written by a " + in.bytes("precision") + " build, this is a " + precisionName() + " build");
  const json saved = json::parse(in.bytes("scene"));
  const std::string difference = firstDifference(saved, comparableScene(scene_.raw));
  if (!difference.empty())
    refuse("it was written for another scene; they differ at " + difference + " (only output.* and simulation.stopAt may change)");

  ParticleFields& fields = fluid_->fields();
  std::string names;
  for (auto& f : fields.all()) names += f->name() + "\n";
  if (in.bytes("fields") != names) refuse("its particle fields differ from this simulation's (a plugin added or removed?)");
  const std::size_t n = in.get<std::size_t>("particles");
  fields.reserve(std::max({fields.capacity(), in.get<std::size_t>("capacity"), n}));
  fields.resize(n);
  for (auto& f : fields.all()) {
    if (in.get<int>("fieldType/" + f->name()) != int(f->type())) refuse("field '" + f->name() + "' has another type");
    const std::string& bytes = in.bytes("field/" + f->name());
    const std::size_t valueBytes = f->type() == FieldType::Index ? sizeof(Index) : std::size_t(f->components()) * sizeof(Real);
    if (bytes.size() != n * valueBytes) refuse("field '" + f->name() + "' has the wrong size");
    if (n > 0) std::memcpy(f->data(), bytes.data(), bytes.size());
  }

  const auto bodies = in.getVector<BodyState>("bodies");
  if (bodies.size() != (bodies_ ? bodies_->count() : 0)) refuse("its moving bodies differ from the scene's");
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    MovingBodyState b = bodies_->state(i);
    setState(b, bodies[i]);
    bodies_->restoreState(i, b);
  }
  if (bodies_) {
    // The boundary follows the bodies, as after any step.
    boundaryModel_->follow(bodies_->poses(false));
    boundaryModel_->markMoved();
  }
  const auto emitters = in.getVector<Emitter::State>("emitters");
  if (emitters.size() != emitters_.size()) refuse("its emitters differ from the scene's");
  for (std::size_t i = 0; i < emitters.size(); ++i) emitters_[i].setState(emitters[i]);

  time_ = in.get<double>("time");
  dt_ = in.get<Real>("dt");
  dtPrevious_ = in.get<Real>("dtPrevious");
  timeStepCap_ = in.get<Real>("timeStepCap");
  // Absent from checkpoints written before timeStepControl existed (they ran "cfl").
  lastPressureIterations_ = in.has("lastPressureIterations") ? in.get<int>("lastPressureIterations") : 0;
  stats_ = in.get<SimulationStats>("stats");
  nextId_ = in.get<Index>("nextId");
  emittersEndTime_ = in.get<double>("emittersEndTime");
  nextProbeRow_ = in.get<std::size_t>("nextProbeRow");
  // Absent from checkpoints written before probe rows were window means (their rows were not).
  if (probes_ && in.has("probeWindow/time"))
    probes_->setWindow({in.getVector<double>("probeWindow/impulses"), in.get<double>("probeWindow/time"),
                        in.get<std::size_t>("probeWindow/steps")});
  nextCheckpoint_ = in.get<std::size_t>("nextCheckpoint");
  checkpointsWritten_ = in.get<std::size_t>("checkpointsWritten");
  resumed_.pending = true;
  resumed_.directory = in.bytes("output/directory");
  resumed_.nextFrame = in.get<std::size_t>("nextFrame");
  resumed_.frames = framesFromText(in.bytes("output/frames"));
  resumed_.bodyFrames = framesFromText(in.bytes("output/bodyFrames"));
  resumed_.bodyCsv = in.bytes("output/bodyCsv");
  restarted_ = true;
  pressureFieldStep_ = ~std::size_t(0);  // computed again from the restored state when read
  log_(LogLevel::Info, "restarted from " + path + " at t = " + std::to_string(double(time_)) + " s, step " + std::to_string(stats_.steps));
}

void Simulation::writeCheckpointIfDue() {
  // Checkpoint k is due once the simulated time reaches k interval (within half a step).
  const Real interval = scene_.output.checkpointInterval;
  if (!(interval > 0) || time_ + Real(0.5) * dt_ < Real(nextCheckpoint_) * interval) return;
  nextCheckpoint_ = std::size_t(std::floor((time_ + Real(0.5) * dt_) / interval)) + 1;
  ++checkpointsWritten_;
  char file[64];
  std::snprintf(file, sizeof(file), "checkpoint_%05zu.state", nextCheckpoint_ - 1);
  saveCheckpoint((std::filesystem::path(scene_.output.directory) / file).string());
}

}  // namespace consph
