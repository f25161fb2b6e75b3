#include "Simulation/SplishSplashScene.h"

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>

#include "Simulation/FluidBlock.h"
#include "Utilities/Error.h"

namespace consph {

namespace {

// SPlisHSPlasH's top-level keys (its doc/file_format.md, 2.16).
const std::vector<std::string> kSplishSplashTopLevel = {"Configuration", "Materials", "FluidBlocks", "FluidModels",
                                                        "RigidBodies",   "Emitters",  "AnimationFields"};

// Keys consph cannot honour, each warned once: the key, why, and every JSON path it appears at.
class UnhonouredKeys {
 public:
  void add(const std::string& key, const std::string& path, const std::string& why) {
    for (Entry& e : entries_)
      if (e.key == key) {
        e.paths.push_back(path);
        return;
      }
    entries_.push_back({key, why, {path}});
  }
  void report(const LogSink& log) const {
    if (!log) return;
    for (const Entry& e : entries_) {
      std::string where;
      for (const std::string& p : e.paths) where += (where.empty() ? "" : ", ") + p;
      log(LogLevel::Warning, "SPlisHSPlasH key '" + e.key + "' not honoured: " + e.why + " (" + where + ")");
    }
  }

 private:
  struct Entry {
    std::string key, why;
    std::vector<std::string> paths;
  };
  std::vector<Entry> entries_;  // in the order first met
};

// Why a key is not honoured, for the keys that are SPlisHSPlasH's but have no consph meaning.
using Reasons = std::map<std::string, std::string>;

const char* kDisplayOnly = "display only (consph has no viewer)";

// One SPlisHSPlasH object read key by key: every key taken is honoured; finish() warns the rest.
class SourceObject {
 public:
  SourceObject(const json& value, std::string path, UnhonouredKeys& unhonoured)
      : value_(value), path_(std::move(path)), unhonoured_(unhonoured) {
    if (!value_.is_object()) throw InputError((path_.empty() ? "scene" : path_) + ": expected an object");
  }

  std::string pathOf(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }
  const std::string& path() const { return path_; }
  bool has(const std::string& key) const { return value_.contains(key); }

  // The value at `key` (nullptr when absent); the key counts as honoured.
  const json* take(const std::string& key) {
    auto it = value_.find(key);
    if (it == value_.end()) return nullptr;
    taken_.insert(key);
    return &*it;
  }

  double number(const std::string& key, double fallback) {
    const json* v = take(key);
    if (!v) return fallback;
    if (!v->is_number()) throw InputError(pathOf(key) + ": expected a number");
    return v->get<double>();
  }
  int integer(const std::string& key, int fallback) {
    const json* v = take(key);
    if (!v) return fallback;
    if (!v->is_number() || v->get<double>() != std::floor(v->get<double>()))
      throw InputError(pathOf(key) + ": expected an integer");
    return v->get<int>();
  }
  // SPlisHSPlasH reads its flags from booleans or numbers (0: false).
  bool flag(const std::string& key, bool fallback) {
    const json* v = take(key);
    if (!v) return fallback;
    if (v->is_boolean()) return v->get<bool>();
    if (v->is_number()) return v->get<double>() != 0;
    throw InputError(pathOf(key) + ": expected a boolean");
  }
  std::string text(const std::string& key, const std::string& fallback) {
    const json* v = take(key);
    if (!v) return fallback;
    if (!v->is_string()) throw InputError(pathOf(key) + ": expected a string");
    return v->get<std::string>();
  }
  // [x, y, z]; with `scalarAllowed` a single number s stands for [s, s, s] (SPlisHSPlasH's scales).
  Vector3r vector3(const std::string& key, const Vector3r& fallback, bool scalarAllowed = false) {
    const json* v = take(key);
    if (!v) return fallback;
    if (scalarAllowed && v->is_number()) return Vector3r::Constant(Real(v->get<double>()));
    if (!v->is_array() || v->size() != 3 || !(*v)[0].is_number() || !(*v)[1].is_number() || !(*v)[2].is_number())
      throw InputError(pathOf(key) + ": expected an array of 3 numbers");
    return Vector3r(Real((*v)[0].get<double>()), Real((*v)[1].get<double>()), Real((*v)[2].get<double>()));
  }

  // Marks `key` as not honoured, for `why` (when present).
  void unhonoured(const std::string& key, const std::string& why) {
    if (take(key)) unhonoured_.add(key, pathOf(key), why);
  }

  // Every key not taken is warned: with its reason from `reasons`, or as a key SPlisHSPlasH's
  // format does not have (a typo, or one of a later version).
  void finish(const Reasons& reasons) {
    for (auto it = value_.begin(); it != value_.end(); ++it) {
      if (taken_.count(it.key())) continue;
      auto r = reasons.find(it.key());
      unhonoured_.add(it.key(), pathOf(it.key()), r != reasons.end() ? r->second : "not a key consph knows in this SPlisHSPlasH block");
    }
  }

 private:
  const json& value_;
  std::string path_;
  UnhonouredKeys& unhonoured_;
  std::set<std::string> taken_;
};

json toJson(const Vector3r& v) { return json::array({double(v[0]), double(v[1]), double(v[2])}); }

// A file name of the SPlisHSPlasH scene (relative to its folder) as the consph scene in
// `targetDir` names it.
std::string rebasePath(const std::string& file, const std::string& sceneDir, const std::string& targetDir) {
  namespace fs = std::filesystem;
  const fs::path p(file);
  if (p.is_absolute()) return file;
  const fs::path from = fs::absolute(sceneDir.empty() ? fs::path(".") : fs::path(sceneDir)).lexically_normal();
  const fs::path to = fs::absolute(targetDir.empty() ? fs::path(".") : fs::path(targetDir)).lexically_normal();
  if (from == to) return file;
  return (from / p).lexically_normal().lexically_relative(to).string();
}

// The rotation SPlisHSPlasH builds from rotationAxis and rotationAngle (about the normalised axis).
Matrix3r rotation(const Vector3r& axis, Real angle) {
  if (axis.norm() == 0) return Matrix3r::Identity();
  return Eigen::AngleAxis<Real>(angle, axis.normalized()).toRotationMatrix();
}

// SPlisHSPlasH's pressure solvers by simulationMethod id, and the consph plugin running each
// (empty: consph has none).
struct SolverId {
  const char* splishsplash;
  const char* consph;
};
const SolverId kSolvers[] = {{"WCSPH", "WCSPH"}, {"PCISPH", ""}, {"PBF", ""}, {"IISPH", "IISPH"},
                             {"DFSPH", "DFSPH"}, {"Projective Fluids", ""}, {"ICSPH", ""}};

// A solver's SPlisHSPlasH parameters -> consph's.
const std::map<std::string, std::vector<std::pair<std::string, std::string>>> kSolverParams = {
    {"DFSPH",
     {{"minIterations", "minIterations"},
      {"maxIterations", "maxIterations"},
      {"maxError", "maxError"},
      {"maxIterationsV", "maxIterationsDivergence"},
      {"maxErrorV", "maxErrorDivergence"},
      {"enableDivergenceSolver", "enableDivergenceSolver"}}},
    {"IISPH", {{"minIterations", "minIterations"}, {"maxIterations", "maxIterations"}, {"maxError", "maxError"}}},
    {"WCSPH", {{"stiffness", "stiffness"}, {"exponent", "exponent"}}},
};

// Parameters of solvers that may appear flat in an older Configuration.
const std::vector<std::string> kFlatSolverKeys = {"minIterations", "maxIterations", "maxError", "maxIterationsV", "maxErrorV",
                                                  "enableDivergenceSolver", "stiffness", "exponent", "velocityUpdateMethod",
                                                  "lambda", "pressureClamping"};

// Copies `names`' values (SPlisHSPlasH name -> consph name) from `from` into `to`, where `to` has
// none yet: a namespaced block is read before the flat keys of older scenes, and wins. A flat key
// that loses is still taken (it names the same parameter).
void copyParams(SourceObject& from, const std::vector<std::pair<std::string, std::string>>& names, json& to) {
  for (const auto& [source, target] : names)
    if (const json* v = from.take(source); v && !to.contains(target)) to[target] = *v;
}

struct Configuration {
  json simulation = json::object();
  double radius = 0.025;
  std::string boundaryModel = "VolumeMap";
  json output = json::object();
};

Configuration convertConfiguration(const json& value, UnhonouredKeys& unhonoured) {
  Configuration c;
  SourceObject s(value, "Configuration", unhonoured);
  json& sim = c.simulation;
  c.radius = s.number("particleRadius", 0.025);
  if (!(c.radius > 0)) throw InputError(s.pathOf("particleRadius") + ": must be > 0");
  sim["particleRadius"] = c.radius;
  // Blocks on SPlisHSPlasH's lattices carry its particle volume 0.8 (2r)^3: spacing 2 0.8^(1/3) r.
  sim["particleSpacing"] = 2 * std::cbrt(0.8);
  sim["gravity"] = toJson(s.vector3("gravitation", Vector3r(0, Real(-9.81), 0)));
  const double dt = s.number("timeStepSize", 0.001);
  sim["initialTimeStep"] = dt;
  const int cfl = s.integer("cflMethod", 1);
  if (cfl < 0 || cfl > 2) throw InputError(s.pathOf("cflMethod") + ": expected 0 (fixed step), 1 (CFL) or 2 (CFL and iterations)");
  if (cfl == 0) {
    sim["minTimeStep"] = dt;
    sim["maxTimeStep"] = dt;
    s.unhonoured("cflMinTimeStepSize", "cflMethod 0 runs at the fixed timeStepSize");
    s.unhonoured("cflMaxTimeStepSize", "cflMethod 0 runs at the fixed timeStepSize");
    s.unhonoured("cflFactor", "cflMethod 0 runs at the fixed timeStepSize");
  } else {
    if (cfl == 2) sim["timeStepControl"] = "iterations";
    if (s.has("cflFactor")) sim["cflFactor"] = s.number("cflFactor", 1);
    if (s.has("cflMinTimeStepSize")) sim["minTimeStep"] = s.number("cflMinTimeStepSize", 1e-4);
    if (s.has("cflMaxTimeStepSize")) sim["maxTimeStep"] = s.number("cflMaxTimeStepSize", 0.005);
  }
  if (s.has("stopAt")) {
    const double stopAt = s.number("stopAt", -1);
    if (stopAt >= 0) sim["stopAt"] = stopAt;
    else unhonoured.add("stopAt", s.pathOf("stopAt"), "negative (run forever): consph stops at simulation.stopAt (default 1 s, or --stop-at)");
  }
  if (s.has("enableZSort") && !s.flag("enableZSort", true)) sim["sortInterval"] = 0;
  s.take("enableZSort");
  if (s.flag("sim2D", false)) throw InputError(s.pathOf("sim2D") + ": consph simulates in 3D only");
  for (const char* key : {"kernel", "gradKernel"}) {
    const int k = s.integer(key, 0);
    // consph's kernel is the cubic spline (SPlisHSPlasH's 0, and 4 its tabulated form).
    if (k != 0 && k != 4) unhonoured.add(key, s.pathOf(key), "consph uses the cubic spline kernel (0) only");
  }

  // Pressure solver: simulationMethod, its namespaced block ("DFSPH": {...}) or flat keys.
  const int method = s.integer("simulationMethod", 4);
  if (method < 0 || method > 6)
    throw InputError(s.pathOf("simulationMethod") + ": unknown method id " + std::to_string(method) +
                     "; SPlisHSPlasH's are 0 WCSPH, 1 PCISPH, 2 PBF, 3 IISPH, 4 DFSPH, 5 Projective Fluids, 6 ICSPH");
  const SolverId& id = kSolvers[method];
  const std::string chosen = *id.consph ? id.consph : "DFSPH";
  if (!*id.consph)
    unhonoured.add("simulationMethod", s.pathOf("simulationMethod"),
                   std::to_string(method) + " (" + id.splishsplash + "): consph has no such solver and runs DFSPH, the closest incompressible one");
  json solver = {{"type", chosen}};
  const auto& params = kSolverParams.at(chosen);
  if (*id.consph && s.has(id.splishsplash)) {
    SourceObject block(*s.take(id.splishsplash), s.pathOf(id.splishsplash), unhonoured);
    copyParams(block, params, solver);
    block.finish({});
  }
  copyParams(s, params, solver);  // the flat keys of older scenes
  sim["pressureSolver"] = solver;
  for (const SolverId& other : kSolvers)
    if (&other != &id && s.has(other.splishsplash))
      s.unhonoured(other.splishsplash, "parameters of a pressure solver simulationMethod does not select");
  if (!*id.consph) s.unhonoured(id.splishsplash, "parameters of a solver consph does not have");

  const int boundary = s.integer("boundaryHandlingMethod", 2);
  if (boundary < 0 || boundary > 2)
    throw InputError(s.pathOf("boundaryHandlingMethod") + ": unknown method id " + std::to_string(boundary) +
                     "; SPlisHSPlasH's are 0 particles (Akinci 2012), 1 density maps (Koschier 2017), 2 volume maps (Bender 2019)");
  c.boundaryModel = boundary == 0 ? "Akinci2012" : "VolumeMap";
  if (boundary == 1)
    unhonoured.add("boundaryHandlingMethod", s.pathOf("boundaryHandlingMethod"),
                   "1 (density maps): consph has none and uses volume maps (Bender 2019), the other implicit model");
  sim["boundaryModel"] = {{"type", c.boundaryModel}};

  if (s.has("dataExportFPS")) c.output["fps"] = s.number("dataExportFPS", 25);

  Reasons reasons;
  for (const char* key : {"pause", "pauseAt", "cameraPosition", "cameraLookat", "numberOfStepsPerRenderUpdate", "renderWalls",
                          "cameraMatrix"})
    reasons[key] = kDisplayOnly;
  for (const char* key : {"enablePartioExport", "enableVTKExport", "enableRigidBodyExport", "enableRigidBodyVTKExport",
                          "particleAttributes", "enableAsyncExport", "enableObjectSplitting"})
    reasons[key] = "consph writes .vtu frames of every field at output.fps (--no-output: none)";
  reasons["enableStateExport"] = reasons["stateExportFPS"] = "consph has no state export";
  for (const std::string& key : kFlatSolverKeys) reasons[key] = "a parameter of a pressure solver simulationMethod does not select";
  s.finish(reasons);
  return c;
}

// Non-pressure forces by SPlisHSPlasH method id: its method name (the namespaced block), the
// consph plugin (empty: none) and the parameters mapped.
struct ForceMethod {
  const char* splishsplash;
  const char* consph;
  std::vector<std::pair<std::string, std::string>> params;
};
using ForceTable = std::vector<ForceMethod>;  // index: the method id

const ForceTable kViscosity = {
    {"None", "", {}},
    {"Standard viscosity", "StandardViscosity", {{"viscosity", "viscosity"}, {"viscosityBoundary", "boundaryViscosity"}}},
    {"Bender and Koschier 2017", "", {}},
    {"Peer et al. 2015", "", {}},
    {"Peer et al. 2016", "", {}},
    {"Takahashi et al. 2015 (improved)", "", {}},
    {"Weiler et al. 2018",
     "Weiler2018",
     {{"viscosity", "viscosity"}, {"viscosityBoundary", "boundaryViscosity"}, {"viscoMaxIter", "maxIterations"}, {"viscoMaxError", "maxError"}}},
};
const ForceTable kVorticity = {
    {"None", "", {}},
    {"Bender et al. 2017", "Micropolar", {{"vorticity", "vorticity"}, {"viscosityOmega", "viscosityOmega"}, {"inertiaInverse", "inertiaInverse"}}},
    {"Vorticity confinement", "VorticityConfinement", {{"vorticity", "vorticity"}}},
    {"Liu et al. 2021", "", {}},
};
const ForceTable kDrag = {
    {"None", "", {}},
    {"Macklin et al. 2014", "Macklin2014", {{"drag", "drag"}}},
    {"Gissler et al. 2017", "Gissler2017", {{"drag", "drag"}}},
};
const ForceTable kSurfaceTension = {
    {"None", "", {}},
    {"Becker & Teschner 2007", "", {}},
    {"Akinci et al. 2013", "Akinci2013", {{"surfaceTension", "surfaceTension"}, {"surfaceTensionBoundary", "boundaryAdhesion"}}},
    {"He et al. 2014", "", {}},
    {"Jeske et al. 2023", "", {}},
    {"Zorilla, Ritter, et al. 2020", "", {}},
};

// Every parameter name any method of `table` takes (the flat keys of older scenes).
void addFlatKeys(const ForceTable& table, std::set<std::string>& keys) {
  for (const ForceMethod& m : table)
    for (const auto& p : m.params) keys.insert(p.first);
}

// The force `methodKey` selects in material `m`, appended to `forces`; the namespaced blocks of
// the methods not selected are warned.
void convertForce(SourceObject& m, const std::string& methodKey, const ForceTable& table, json& forces, UnhonouredKeys& unhonoured) {
  const int id = m.integer(methodKey, 0);
  if (id < 0 || id >= int(table.size())) {
    std::string valid;
    for (std::size_t i = 0; i < table.size(); ++i) valid += (i ? ", " : "") + std::to_string(i) + " " + table[i].splishsplash;
    throw InputError(m.pathOf(methodKey) + ": unknown method id " + std::to_string(id) + "; SPlisHSPlasH's are " + valid);
  }
  const ForceMethod& method = table[std::size_t(id)];
  for (std::size_t i = 1; i < table.size(); ++i)
    if (int(i) != id) m.unhonoured(table[i].splishsplash, "parameters of a method " + methodKey + " does not select");
  if (id == 0) return;
  if (!*method.consph) {
    unhonoured.add(methodKey, m.pathOf(methodKey), std::to_string(id) + " (" + method.splishsplash + "): consph has no such method");
    m.unhonoured(method.splishsplash, "parameters of a method consph does not have");
    return;
  }
  json force = {{"type", method.consph}};
  if (m.has(method.splishsplash)) {
    SourceObject block(*m.take(method.splishsplash), m.pathOf(method.splishsplash), unhonoured);
    copyParams(block, method.params, force);
    block.finish({});
  }
  copyParams(m, method.params, force);  // flat keys
  forces.push_back(force);
}

struct Material {
  double density0 = 1000;
  json forces = json::array();
  json removeOutside;  // null, or {"min", "max"}: emitterReuseParticles' box
};

Material convertMaterial(const json& value, const std::string& path, UnhonouredKeys& unhonoured) {
  Material material;
  SourceObject m(value, path, unhonoured);
  m.take("id");
  material.density0 = m.number("density0", 1000);
  // SPlisHSPlasH's order in a step: surface tension, viscosity, vorticity, drag, then XSPH.
  convertForce(m, "surfaceTensionMethod", kSurfaceTension, material.forces, unhonoured);
  convertForce(m, "viscosityMethod", kViscosity, material.forces, unhonoured);
  convertForce(m, "vorticityMethod", kVorticity, material.forces, unhonoured);
  convertForce(m, "dragMethod", kDrag, material.forces, unhonoured);
  // XSPH: a filter every fluid has, off at the coefficient 0.
  {
    json xsph = {{"type", "XSPH"}};
    const std::vector<std::pair<std::string, std::string>> names = {{"xsph", "viscosity"}, {"xsphBoundary", "boundaryViscosity"}};
    if (m.has("XSPH")) {
      SourceObject block(*m.take("XSPH"), m.pathOf("XSPH"), unhonoured);
      copyParams(block, names, xsph);
      block.finish({});
    }
    copyParams(m, names, xsph);
    if (xsph.value("viscosity", 0.0) != 0 || xsph.value("boundaryViscosity", 0.0) != 0) {
      if (!xsph.contains("viscosity")) xsph["viscosity"] = 0.0;
      material.forces.push_back(xsph);
    }
  }
  // Emitted particles that leave the box are taken back for reuse: in consph they are removed
  // (the emitters' budget covers what they emit).
  const bool reuse = m.flag("emitterReuseParticles", false);
  const Vector3r boxMin = m.vector3("emitterBoxMin", Vector3r(-1, -1, -1)), boxMax = m.vector3("emitterBoxMax", Vector3r(1, 1, 1));
  if (reuse) material.removeOutside = {{"min", toJson(boxMin)}, {"max", toJson(boxMax)}};
  Reasons reasons;
  for (const char* key : {"colorField", "colorMapType", "renderMinValue", "renderMaxValue", "maxValue", "minValue"}) reasons[key] = kDisplayOnly;
  reasons["maxEmitterParticles"] = "consph sizes the emitters' budget from their rate and end time";
  reasons["elasticityMethod"] = "consph has no elasticity methods";
  for (const char* key : {"Becker et al. 2009", "Peer et al. 2018", "Kugelstadt et al. 2021"})
    reasons[key] = "parameters of an elasticity method (consph has none)";
  std::set<std::string> flat;
  for (const ForceTable* t : {&kViscosity, &kVorticity, &kDrag, &kSurfaceTension}) addFlatKeys(*t, flat);
  for (const std::string& key : flat) reasons[key] = "a parameter of a method the material does not select";
  m.finish(reasons);
  return material;
}

// A fluid object's material id ("Fluid" when not given), read from `o`.
std::string materialId(SourceObject& o) { return o.text("id", "Fluid"); }

json convertRigidBody(const json& value, const std::string& path, const std::string& sceneDir, const std::string& targetDir,
                      UnhonouredKeys& unhonoured) {
  SourceObject b(value, path, unhonoured);
  json o = json::object();
  const std::string mesh = b.text("geometryFile", "");
  if (mesh.empty()) throw InputError(b.pathOf("geometryFile") + ": required string is missing (the body's mesh file)");
  o["mesh"] = rebasePath(mesh, sceneDir, targetDir);
  o["translation"] = toJson(b.vector3("translation", Vector3r::Zero()));
  o["rotationAxis"] = toJson(b.vector3("rotationAxis", Vector3r(0, 0, 1)));
  o["rotationAngle"] = b.number("rotationAngle", 0);
  o["scale"] = toJson(b.vector3("scale", Vector3r::Ones(), true));
  // SPlisHSPlasH's container flag is the map's; consph needs it for every boundary model.
  o["inverted"] = b.flag("mapInvert", false);
  if (b.flag("isDynamic", false)) {
    o["dynamic"] = true;
    o["density"] = b.number("density", 1000);
    if (b.has("velocity")) o["velocity"] = toJson(b.vector3("velocity", Vector3r::Zero()));
    if (b.has("angularVelocity")) o["angularVelocity"] = toJson(b.vector3("angularVelocity", Vector3r::Zero()));
  } else {
    b.unhonoured("density", "a static body has no mass in consph");
    b.unhonoured("velocity", "a static body cannot move in consph");
    b.unhonoured("angularVelocity", "a static body cannot move in consph");
  }
  if (b.has("friction")) o["friction"] = b.number("friction", 0.5);
  // The same shift of the map's surface into the fluid (Phi - thickness).
  if (const double thickness = b.number("mapThickness", 0); thickness != 0) o["mapThickness"] = thickness;
  if (b.flag("isAnimated", false)) unhonoured.add("isAnimated", b.pathOf("isAnimated"), "consph animates bodies by a prescribed velocity (\"animated\"), not by script: the body is static");
  Reasons reasons;
  reasons["color"] = reasons["isWall"] = kDisplayOnly;
  reasons["mapResolution"] =
      "a cell count for SPlisHSPlasH's cubic-interpolated grid; consph's maps are trilinear and need cells of about r "
      "(simulation.boundaryModel.cellSize, default 1 r; per object: the boundary's mapCellSize)";
  reasons["samplingMode"] = "consph samples surfaces on its own regular grid (simulation.boundaryModel.samplingDistance)";
  reasons["particleFile"] = "consph samples the body's surface from geometryFile itself";
  reasons["mapFile"] = "consph builds the volume map from geometryFile itself";
  for (const char* key : {"id", "restitution", "collisionObjectType", "collisionObjectScale", "testMesh", "invertSDF", "collisionObjectFileName"})
    reasons[key] = "a PositionBasedDynamics collision setting (consph's rigid contact works on the boundary samples)";
  b.finish(reasons);
  return o;
}

// Calls `convert(item, path)` for each item of the array at `key` of `top` (none when absent).
template <class Convert>
void forEachItem(SourceObject& top, const std::string& key, Convert&& convert) {
  const json* list = top.take(key);
  if (!list) return;
  if (!list->is_array()) throw InputError(top.pathOf(key) + ": expected an array");
  for (std::size_t i = 0; i < list->size(); ++i) convert((*list)[i], top.pathOf(key) + "[" + std::to_string(i) + "]");
}

}  // namespace

bool isSplishSplashScene(const json& scene) {
  if (!scene.is_object() || scene.contains("fluids")) return false;
  for (const std::string& key : kSplishSplashTopLevel)
    if (scene.contains(key)) return true;
  return false;
}

json convertSplishSplashScene(const json& scene, const std::string& sceneDir, const std::string& targetDir, const std::string& name,
                              const LogSink& log) {
  UnhonouredKeys unhonoured;
  SourceObject top(scene, "", unhonoured);
  static const json empty = json::object();
  const json* configuration = top.take("Configuration");
  Configuration config = convertConfiguration(configuration ? *configuration : empty, unhonoured);
  const double r = config.radius;

  std::set<std::string> materialIds;  // the materials the fluid objects use
  json blocks = json::array(), emitters = json::array(), particleFiles = json::array(), meshVolumes = json::array();

  // FluidBlocks: boxes on SPlisHSPlasH's lattices, scale and translation applied to the corners.
  forEachItem(top, "FluidBlocks", [&](const json& item, const std::string& path) {
    SourceObject b(item, path, unhonoured);
    materialIds.insert(materialId(b));
    const int mode = b.integer("denseMode", 0);
    if (mode < 0 || mode > 2) throw InputError(b.pathOf("denseMode") + ": expected 0 (regular), 1 (more dense) or 2 (dense)");
    const Vector3r start = b.vector3("start", Vector3r::Zero()), end = b.vector3("end", Vector3r::Ones());
    const Vector3r scale = b.vector3("scale", Vector3r::Ones(), true), translation = b.vector3("translation", Vector3r::Zero());
    const FluidBlock block{scale.cwiseProduct(start) + translation, scale.cwiseProduct(end) + translation,
                           b.vector3("initialVelocity", Vector3r::Zero()), BlockLattice(1 + mode)};
    if (b.vector3("initialAngularVelocity", Vector3r::Zero()).norm() != 0)
      unhonoured.add("initialAngularVelocity", b.pathOf("initialAngularVelocity"), "consph fluid objects start with one velocity");
    if (blockCounts(block, Real(0), Real(r))[0] == 0) {
      // As SPlisHSPlasH does: a block too thin for its lattice is skipped with a warning.
      if (log) log(LogLevel::Warning, path + ": the fluid block is empty on its lattice (denseMode " + std::to_string(mode) + ") and is skipped, as SPlisHSPlasH skips it");
    } else {
      blocks.push_back({{"min", toJson(block.min)},
                        {"max", toJson(block.max)},
                        {"velocity", toJson(block.velocity)},
                        {"lattice", blockLatticeNames()[std::size_t(block.lattice)]}});
    }
    b.finish({{"visMesh", "a mesh for SPlisHSPlasH's MeshSkinning tool"}});
  });

  // FluidModels: a particle file, or a closed OBJ/PLY mesh whose volume is sampled (as
  // SPlisHSPlasH decides by the file's extension).
  forEachItem(top, "FluidModels", [&](const json& item, const std::string& path) {
    SourceObject m(item, path, unhonoured);
    materialIds.insert(materialId(m));
    const std::string file = m.text("particleFile", "");
    if (file.empty()) throw InputError(m.pathOf("particleFile") + ": required string is missing (a particle file or a closed mesh)");
    std::string extension = std::filesystem::path(file).extension().string();
    for (char& c : extension) c = char(std::tolower(static_cast<unsigned char>(c)));
    const bool mesh = extension == ".obj" || extension == ".ply";
    json out = {{"translation", toJson(m.vector3("translation", Vector3r::Zero()))},
                {"rotationAxis", toJson(m.vector3("rotationAxis", Vector3r(0, 0, 1)))},
                {"rotationAngle", m.number("rotationAngle", 0)}};
    const Vector3r scale = m.vector3("scale", Vector3r::Ones(), true);
    if (m.has("initialVelocity")) out["velocity"] = toJson(m.vector3("initialVelocity", Vector3r::Zero()));
    if (m.vector3("initialAngularVelocity", Vector3r::Zero()).norm() != 0)
      unhonoured.add("initialAngularVelocity", m.pathOf("initialAngularVelocity"), "consph fluid objects start with one velocity");
    if (mesh) {
      out["mesh"] = rebasePath(file, sceneDir, targetDir);
      out["scale"] = toJson(scale);
      // SPlisHSPlasH samples the scaled mesh in its own frame, then rotates the points.
      out["lattice"] = "splishsplashRegular";
      const int mode = m.integer("denseMode", 0);
      if (mode != 0) unhonoured.add("denseMode", m.pathOf("denseMode"), "a mesh volume is sampled with denseMode 0 (regular) only");
      if (m.flag("invert", false)) unhonoured.add("invert", m.pathOf("invert"), "consph fills a mesh's inside only");
      m.unhonoured("resolutionSDF", "consph tells inside from outside by the mesh's winding number, exactly");
      meshVolumes.push_back(out);
    } else {
      out["file"] = rebasePath(file, sceneDir, targetDir);
      // SPlisHSPlasH's particle import scales uniformly by the first component.
      if (scale.cwiseAbs().maxCoeff() != scale.cwiseAbs().minCoeff())
        unhonoured.add("scale", m.pathOf("scale"), "a particle file is scaled uniformly by its first component, as in SPlisHSPlasH");
      out["scale"] = toJson(Vector3r::Constant(scale[0]));
      m.unhonoured("denseMode", "a particle file's particles are taken as they are");
      particleFiles.push_back(out);
    }
    m.finish({{"visMesh", "a mesh for SPlisHSPlasH's MeshSkinning tool"}});
  });

  // Emitters: SPlisHSPlasH sizes nozzles in particles (2r apart) and emits along the rotated x axis.
  forEachItem(top, "Emitters", [&](const json& item, const std::string& path) {
    SourceObject e(item, path, unhonoured);
    materialIds.insert(materialId(e));
    const int type = e.integer("type", 0);
    if (type != 0 && type != 1) throw InputError(e.pathOf("type") + ": expected 0 (box) or 1 (circle)");
    const double width = e.number("width", 5), height = e.number("height", 5);
    if (width < 1 || (type == 0 && height < 1)) throw InputError(e.pathOf("width") + ": a nozzle is at least one particle wide and high");
    const Matrix3r R = rotation(e.vector3("rotationAxis", Vector3r(0, 0, 1)), Real(e.number("rotationAngle", 0)));
    json out = {{"position", toJson(e.vector3("translation", Vector3r::Zero()))},
                {"direction", toJson(R.col(0))},
                {"speed", e.number("velocity", 1)},
                {"start", e.number("emitStartTime", 0)}};
    if (type == 0) {
      out["shape"] = "rectangle";
      out["width"] = width * 2 * r;
      out["height"] = height * 2 * r;
    } else {
      out["shape"] = "circle";
      out["radius"] = width * r;
      e.unhonoured("height", "a circular nozzle has only a width");
    }
    if (e.has("emitEndTime")) out["end"] = e.number("emitEndTime", 1e9);
    emitters.push_back(out);
    e.finish({});
  });
  // Not a key, so not in the unhonoured list: a geometry SPlisHSPlasH adds by itself.
  if (!emitters.empty() && log)
    log(LogLevel::Warning, "Emitters: SPlisHSPlasH surrounds each nozzle with a boundary box (a cylinder for a circular one); "
                           "consph adds none: add a boundary object where fluid can flow back onto a nozzle");

  // Materials: consph runs one fluid, so the fluid objects must share one material.
  if (materialIds.size() > 1) {
    std::string ids;
    for (const std::string& id : materialIds) ids += (ids.empty() ? "'" : ", '") + id + "'";
    throw InputError("FluidBlocks/FluidModels/Emitters: the scene's fluid objects use the materials " + ids + "; consph runs one fluid per scene");
  }
  const std::string fluidId = materialIds.empty() ? "Fluid" : *materialIds.begin();
  Material material;
  bool found = false;
  forEachItem(top, "Materials", [&](const json& item, const std::string& path) {
    if (!item.is_object()) throw InputError(path + ": expected an object");
    if (item.contains("id") && !item["id"].is_string()) throw InputError(path + ".id: expected a string");
    const std::string id = item.value("id", std::string("Fluid"));
    if (id == fluidId && !found) {
      material = convertMaterial(item, path, unhonoured);
      found = true;
    } else {
      unhonoured.add("Materials", path, "material '" + id + "' is used by no fluid object");
    }
  });
  json fluid = {{"name", fluidId.empty() ? "fluid" : fluidId}, {"density0", material.density0}, {"forces", material.forces}};
  if (!material.removeOutside.is_null()) fluid["removeOutside"] = material.removeOutside;
  if (!blocks.empty()) fluid["blocks"] = blocks;
  if (!particleFiles.empty()) fluid["particleFiles"] = particleFiles;
  if (!meshVolumes.empty()) fluid["meshVolumes"] = meshVolumes;
  if (!emitters.empty()) fluid["emitters"] = emitters;
  if (blocks.empty() && emitters.empty() && particleFiles.empty() && meshVolumes.empty())
    throw InputError("FluidBlocks: the scene has no fluid (no non-empty FluidBlocks, no FluidModels, no Emitters)");

  json boundaries = json::array();
  forEachItem(top, "RigidBodies", [&](const json& item, const std::string& path) {
    boundaries.push_back(convertRigidBody(item, path, sceneDir, targetDir, unhonoured));
  });

  top.finish({{"AnimationFields", "consph has no animation fields"},
              {"Simulation", "PositionBasedDynamics settings (consph integrates rigid bodies itself)"}});
  unhonoured.report(log);

  json out = {{"name", name},
              {"description", "converted from a SPlisHSPlasH scene (docs/splishsplash.md)"},
              {"simulation", config.simulation},
              {"fluids", json::array({fluid})},
              {"boundaries", boundaries}};
  if (!config.output.empty()) out["output"] = config.output;
  return out;
}

}  // namespace consph
