#include "Simulation/Scene.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <utility>

#include "Simulation/JsonLimits.h"
#include "Simulation/MeshVolumeSampling.h"
#include "Simulation/SceneFile.h"
#include "Simulation/SplishSplashScene.h"
#include "Utilities/Error.h"
#include "Utilities/MeshClosure.h"
#include "Utilities/PointFile.h"
#include "Utilities/Text.h"

namespace consph {

namespace {
// The scene's names of the treatments, written once: the parser, the summary and the warnings read them.
constexpr std::pair<BoundaryPressure, const char*> kBoundaryPressureNames[] = {
    {BoundaryPressure::Consistent, "consistent"},
    {BoundaryPressure::Mirroring, "mirroring"},
    {BoundaryPressure::Extrapolation, "extrapolation"},
};
}  // namespace

const char* boundaryPressureName(BoundaryPressure b) {
  for (const auto& [value, name] : kBoundaryPressureNames)
    if (value == b) return name;
  return "?";
}

json readJsonFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError("cannot open scene file '" + path + "'");
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string text = buffer.str();
  checkJsonLimits(text, path);
  try {
    return json::parse(text);
  } catch (const json::parse_error& e) {
    std::string what = e.what();
    const auto colon = what.find(": ", what.find("parse error"));
    if (colon != std::string::npos) what = what.substr(colon + 2);
    // e.byte is 1-based: the offending byte itself.
    throw InputError(path + ":" + lineColumn(text, e.byte > 0 ? e.byte - 1 : 0) + ": malformed JSON: " + what);
  } catch (const json::exception& e) {
    throw InputError(path + ": malformed JSON: " + e.what());
  }
}

void applyOverride(json& scene, const std::string& dottedPath, const std::string& valueText) {
  json value;
  checkJsonLimits(valueText, "--set " + dottedPath);
  try {
    value = json::parse(valueText);
  } catch (const json::parse_error&) {
    value = valueText;  // --set x.type=WCSPH: a bare word is a string
  }
  json* node = &scene;
  std::stringstream parts(dottedPath);
  std::string part, walked;
  std::vector<std::string> keys;
  while (std::getline(parts, part, '.')) keys.push_back(part);
  if (keys.empty() || dottedPath.empty()) throw InputError("--set: empty key path");
  for (std::size_t i = 0; i < keys.size(); ++i) {
    const std::string& k = keys[i];
    walked += (walked.empty() ? "" : ".") + k;
    const bool last = i + 1 == keys.size();
    if (node->is_array()) {
      std::size_t idx = 0;
      try {
        idx = std::stoul(k);
      } catch (...) {
        throw InputError("--set " + dottedPath + ": '" + walked + "' indexes an array; use a number");
      }
      if (idx >= node->size()) throw InputError("--set " + dottedPath + ": index " + k + " is past the end of the array");
      node = &(*node)[idx];
    } else {
      if (node->is_null()) *node = json::object();
      if (!node->is_object()) throw InputError("--set " + dottedPath + ": '" + walked + "' is inside a non-object value");
      node = &(*node)[k];
    }
    if (last) *node = value;
  }
}

namespace {

std::string at(const std::string& path, const std::string& key) { return path.empty() ? key : path + "." + key; }

// The value of `key` in `object` (at `path`), null when the key is absent. A null written in the
// scene is not an absent key: it would stand for the default silently, so it is a wrong type
// (`expected` says what the key takes).
const json& child(const json& object, const std::string& path, const std::string& key, const char* expected) {
  static const json null;
  if (!object.is_object()) return null;
  auto it = object.find(key);
  if (it == object.end()) return null;
  if (it->is_null()) throw InputError(at(path, key) + ": expected " + expected + ", got null (leave the key out for its default)");
  return *it;
}

void expectObject(const json& v, const std::string& path) {
  if (!v.is_object()) throw InputError(path + ": expected an object");
}

// A fluid's name becomes file names (NAME_00001.vtu, NAME.pvd) and XML attributes in the .pvd:
// nothing that leaves the output folder, hides the file or breaks the XML.
void checkFileName(const std::string& name, const std::string& path) {
  if (name.empty()) throw InputError(path + ": must not be empty (it names the output files)");
  if (!printableUtf8(name)) throw InputError(path + ": must be printable UTF-8 text (it names the output files)");
  if (name.find_first_of("/\\") != std::string::npos || name.find("..") != std::string::npos || name[0] == '.')
    throw InputError(path + ": '" + name + "' must not contain '/', '\\' or '..' or start with '.' (it names the output files)");
  if (name.find_first_of("<>&\"'") != std::string::npos)
    throw InputError(path + ": '" + name + "' must not contain < > & \" or ' (it is written into the .pvd's XML)");
}

// A boundary's name is a field of bodies.csv and appears in messages.
void checkObjectName(const std::string& name, const std::string& path) {
  if (!printableUtf8(name) || name.find_first_of(",\"") != std::string::npos)
    throw InputError(path + ": must be printable UTF-8 text without a comma or a quote (it is a field of bodies.csv)");
}

// The index of an earlier item of `list` equal to item i, `ignored` left out of the comparison;
// npos when there is none.
std::size_t earlierEqual(const json& list, std::size_t i, const std::string& ignored = "") {
  json item = list[i];
  if (item.is_object()) item.erase(ignored);
  for (std::size_t k = 0; k < i; ++k) {
    json other = list[k];
    if (other.is_object()) other.erase(ignored);
    if (other == item) return k;
  }
  return std::string::npos;
}

std::string lowerCase(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return s;
}

std::string resolvePath(const std::string& baseDir, const std::string& file) {
  std::filesystem::path p(file);
  if (p.is_relative()) p = std::filesystem::path(baseDir) / p;
  return p.lexically_normal().string();
}

// The transform keys a boundary, a particle file and a mesh volume share: x -> R (scale .* x) + t.
struct PlacementKeys {
  Vector3r translation, scale, axis;
  Real angle;
};
const std::vector<ParamSpec>& placementSpecs() {
  static const std::vector<ParamSpec> specs = {
      {"translation", ParamType::Vector3, json::array({0, 0, 0}), "translation, m"},
      {"rotationAxis", ParamType::Vector3, json::array({0, 0, 1}), "rotation axis"},
      {"rotationAngle", ParamType::Real, 0.0, "rotation angle about rotationAxis, radians"},
      {"scale", ParamType::Vector3, json::array({1, 1, 1}), "scale per axis, applied first"}};
  return specs;
}
PlacementKeys placement(const Params& p) {
  PlacementKeys k{p.vector3("translation"), p.vector3("scale"), p.vector3("rotationAxis"), p.real("rotationAngle")};
  if (k.scale.cwiseAbs().minCoeff() == 0) throw InputError(p.pathOf("scale") + ": must not be 0 on any axis (the object would be flat)");
  if (k.angle != 0 && k.axis.isZero(0)) throw InputError(p.pathOf("rotationAxis") + ": must not be the zero vector when rotationAngle is not 0");
  return k;
}
Matrix3r rotationOf(const PlacementKeys& k) {
  return k.angle == 0 ? Matrix3r::Identity() : Matrix3r(Eigen::AngleAxis<Real>(k.angle, k.axis.stableNormalized()).toRotationMatrix());
}

// "dynamic", "density", "velocity", "angularVelocity", "animated" and "hinge" of a boundary.
void parseBodyMotion(const json& b, const Params& p, BoundaryObject& o, const LogSink& log) {
  const std::string& path = o.path;
  const bool dynamic = p.boolean("dynamic"), animated = b.contains("animated");
  if (dynamic && animated) throw InputError(path + ": an object is either \"dynamic\" or \"animated\", not both");
  if ((dynamic || animated) && o.inverted) throw InputError(path + ".inverted: a moving object cannot be a container");
  if (!dynamic) {
    for (const char* key : {"density", "velocity", "angularVelocity", "hinge"})
      if (b.contains(key)) throw InputError(at(path, key) + ": only a dynamic object (\"dynamic\": true) takes this key");
  }
  if (dynamic) {
    o.motion = BodyMotion::Dynamic;
    if (!b.contains("density")) throw InputError(at(path, "density") + ": required number is missing (a dynamic body needs a density, kg/m^3)");
    Params dp(json{{"density", b["density"]}}, path, {{"density", ParamType::Real, json(), "density of a dynamic body, kg/m^3", 1e-6, 1e9}}, log, {});
    o.density = dp.real("density");
    o.velocity = p.vector3("velocity");
    o.angularVelocity = p.vector3("angularVelocity");
  }
  if (animated) {
    o.motion = BodyMotion::Animated;
    expectObject(b["animated"], at(path, "animated"));
    Params ap(b["animated"], at(path, "animated"),
              {{"velocity", ParamType::Vector3, json::array({0, 0, 0}), "prescribed velocity, m/s"},
               {"angularVelocity", ParamType::Vector3, json::array({0, 0, 0}), "prescribed angular velocity about the centre, rad/s"}},
              log, {});
    o.velocity = ap.vector3("velocity");
    o.angularVelocity = ap.vector3("angularVelocity");
  }
  if (b.contains("hinge")) {
    const std::string hp = at(path, "hinge");
    expectObject(b["hinge"], hp);
    Params h(b["hinge"], hp,
             {{"point", ParamType::Vector3, json(), "a point on the axle, m"},
              {"axis", ParamType::Vector3, json(), "axle direction (normalised)"}},
             log, {"motor"});
    o.hinge.enabled = true;
    o.hinge.point = h.vector3("point");
    const Vector3r axis = h.vector3("axis");
    if (axis.isZero(0)) throw InputError(at(hp, "axis") + ": must not be the zero vector");
    o.hinge.axis = axis.stableNormalized();
    if (b["hinge"].contains("motor")) {
      expectObject(b["hinge"]["motor"], at(hp, "motor"));
      Params m(b["hinge"]["motor"], at(hp, "motor"),
               {{"targetVelocity", ParamType::Real, json(), "target angular velocity about the axis, rad/s"},
                {"maxTorque", ParamType::Real, json(), "largest torque the motor exerts, N m", 0, 1e12}},
               log, {});
      o.hinge.motor = true;
      o.hinge.targetVelocity = m.real("targetVelocity");
      o.hinge.maxTorque = m.real("maxTorque");
    }
  }
}

BoundaryObject parseBoundary(const json& b, const std::string& path, const std::string& baseDir, const LogSink& log) {
  expectObject(b, path);
  const bool hasBox = b.contains("box"), hasMesh = b.contains("mesh");
  if (hasBox == hasMesh) throw InputError(path + ": give exactly one of \"box\" or \"mesh\"");
  std::vector<ParamSpec> specs = {{"name", ParamType::String, "", "name of the object (for output and messages)"},
                                  {"mesh", ParamType::String, "", "mesh file (OBJ, PLY, STL, ...), relative to the scene file"}};
  specs.insert(specs.end(), placementSpecs().begin(), placementSpecs().end());
  specs.insert(specs.end(),
           {{"inverted", ParamType::Bool, false, "the fluid is inside the object (a container)"},
            {"dynamic", ParamType::Bool, false, "a rigid body moved by gravity and the fluid (two-way coupling)"},
            {"velocity", ParamType::Vector3, json::array({0, 0, 0}), "initial velocity of a dynamic body's centre of mass, m/s"},
            {"angularVelocity", ParamType::Vector3, json::array({0, 0, 0}), "initial angular velocity of a dynamic body, rad/s"},
            {"friction", ParamType::Real, 0.5,
             "Coulomb friction coefficient in rigid contact (a pair of objects uses sqrt(mu_a mu_b); 0: frictionless)", 0, 10},
            {"mapCellSize", ParamType::Real, 0.0,
             "VolumeMap: this object's map cell size in particle radii (0: the model's cellSize)", 0, 8},
            {"mapThickness", ParamType::Real, 0.0,
             "VolumeMap: the surface moved this far into the fluid, m (SPlisHSPlasH's mapThickness)", 0, 1e6}});
  Params p(b, path, specs, log, {"box", "animated", "hinge", "density"});
  BoundaryObject o;
  o.name = p.string("name");
  if (!o.name.empty()) checkObjectName(o.name, p.pathOf("name"));
  o.path = path;
  o.inverted = p.boolean("inverted");
  o.friction = p.real("friction");
  o.mapCellSize = p.real("mapCellSize");
  if (o.mapCellSize != 0 && o.mapCellSize < Real(0.25))
    throw InputError(p.pathOf("mapCellSize") + ": must be 0 (the model's) or at least 0.25 radii");
  o.mapThickness = p.real("mapThickness");
  parseBodyMotion(b, p, o, log);
  const PlacementKeys placed = placement(p);
  const Vector3r translation = placed.translation, scale = placed.scale, axis = placed.axis;
  const Real angle = placed.angle;
  if (hasBox) {
    expectObject(b["box"], at(path, "box"));
    Params box(b["box"], at(path, "box"),
               {{"min", ParamType::Vector3, json(), "lower corner, m"}, {"max", ParamType::Vector3, json(), "upper corner, m"}},
               log, {});
    Vector3r lo = box.vector3("min"), hi = box.vector3("max");
    if ((hi - lo).minCoeff() <= 0) throw InputError(at(path, "box") + ": max must exceed min on every axis");
    o.mesh = makeBoxMesh(lo, hi, o.inverted);
    if (angle == 0 && scale.minCoeff() > 0) {  // still axis-aligned: sample it on face grids
      o.isBox = true;
      o.boxMin = lo.cwiseProduct(scale) + translation;
      o.boxMax = hi.cwiseProduct(scale) + translation;
    }
  } else {
    o.mesh = loadMesh(resolvePath(baseDir, p.string("mesh")));
    if (o.motion == BodyMotion::Dynamic) {
      // Mass, centre of mass and inertia come from the divergence theorem over the surface,
      // which holds for a closed surface only (an open one still gives a volume, a wrong one).
      const MeshClosure closure = checkClosure(o.mesh);
      if (!closure.closed())
        throw InputError(at(path, "mesh") + ": a dynamic body needs a closed mesh, and '" + p.string("mesh") + "' has " +
                         closure.describe() + ": its volume, centre of mass and inertia would be wrong");
    }
    if (o.inverted)
      for (auto& t : o.mesh.triangles) std::swap(t[1], t[2]);
  }
  transformMesh(o.mesh, scale, axis, angle, translation);
  // Finite inputs can still overflow (a scale of 1e308 on a 2 m mesh), and a box of inf extent
  // would make every grid built over it loop.
  Vector3r lo, hi;
  o.mesh.boundingBox(lo, hi);
  const bool finite = std::all_of(o.mesh.vertices.begin(), o.mesh.vertices.end(), [](const Vector3r& v) { return v.allFinite(); });
  if (!finite || !(hi - lo).allFinite())
    throw InputError(path + ": the transformed object (scale, rotation, translation) has coordinates beyond the range of a number");
  return o;
}

// fluids[].particleFiles[]: particles read from a .ply, .vtu or .bgeo file, placed by the
// transform; their velocities are the file's (rotated with them) unless "velocity" is given.
void parseParticleFile(const json& e, const std::string& path, const std::string& baseDir, const LogSink& log, FluidDescription& fd) {
  std::vector<ParamSpec> specs = placementSpecs();
  specs.push_back({"file", ParamType::String, json(), "point file (.ply, .vtu, .bgeo), relative to the scene file"});
  specs.push_back({"velocity", ParamType::Vector3, json::array({0, 0, 0}), "initial velocity of every particle, m/s (not given: the file's, or 0)"});
  Params p(e, path, specs, log, {});
  const PlacementKeys k = placement(p);
  const Matrix3r R = rotationOf(k);
  const PointFile points = readPointFile(resolvePath(baseDir, p.string("file")));
  if (points.positions.empty()) throw InputError(p.pathOf("file") + ": '" + p.string("file") + "' holds no particles");
  for (std::size_t i = 0; i < points.positions.size(); ++i) {
    const Vector3r x = R * points.positions[i].cwiseProduct(k.scale) + k.translation;
    if (!x.allFinite()) throw InputError(path + ": the transformed particles have coordinates beyond the range of a number");
    fd.sourcePositions.push_back(x);
    fd.sourceVelocities.push_back(p.isSet("velocity") ? p.vector3("velocity")
                                  : points.velocities.empty() ? Vector3r::Zero() : Vector3r(R * points.velocities[i]));
  }
}

// fluids[].meshVolumes[]: the inside of a closed mesh filled on a lattice.
void parseMeshVolume(const json& e, const std::string& path, const std::string& baseDir, Real spacing, Real radius, const LogSink& log,
                     FluidDescription& fd) {
  std::vector<ParamSpec> specs = placementSpecs();
  specs.push_back({"mesh", ParamType::String, json(), "closed mesh (OBJ, PLY, STL, ...), relative to the scene file"});
  specs.push_back({"velocity", ParamType::Vector3, json::array({0, 0, 0}), "initial velocity, m/s"});
  specs.push_back({"lattice", ParamType::String, "cellCentred",
                   "cellCentred (particleSpacing r) or splishsplashRegular (SPlisHSPlasH's FluidModels sampling: 2r voxel centres)",
                   -std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(), {"cellCentred", "splishsplashRegular"}});
  Params p(e, path, specs, log, {});
  const PlacementKeys k = placement(p);
  TriangleMesh mesh = loadMesh(resolvePath(baseDir, p.string("mesh")));
  const MeshClosure closure = checkClosure(mesh);
  if (!closure.closed())
    throw InputError(p.pathOf("mesh") + ": a fluid volume needs a closed mesh, and '" + p.string("mesh") + "' has " + closure.describe());
  // consph's lattice is the world's, as a block's; SPlisHSPlasH samples the scaled mesh in its
  // own frame and then rotates and moves the points.
  const bool worldLattice = p.string("lattice") == "cellCentred";
  if (worldLattice) transformMesh(mesh, k.scale, k.axis, k.angle, k.translation);
  else transformMesh(mesh, k.scale, Vector3r::UnitZ(), 0, Vector3r::Zero());
  Vector3r lo, hi;
  mesh.boundingBox(lo, hi);
  if (!(hi - lo).allFinite()) throw InputError(path + ": the transformed mesh has coordinates beyond the range of a number");
  // Refused before sampling: the lattice over the box would not fit (a scale of 1e6).
  const double step = worldLattice ? double(spacing) : 2 * double(radius);
  double candidates = 1;
  for (int a = 0; a < 3; ++a) candidates *= std::floor(double(hi[a] - lo[a]) / step) + 1;
  if (candidates > 4e9) throw InputError(path + ": the mesh's box holds about " + std::to_string(candidates) + " lattice points, more than a 32-bit index");
  std::vector<Vector3r> x = sampleMeshVolume(mesh, blockLatticeFromName(p.string("lattice")), spacing, radius);
  if (x.empty()) throw InputError(p.pathOf("mesh") + ": no lattice point lies inside the mesh (is it smaller than a particle?)");
  if (!worldLattice) {
    const Matrix3r R = rotationOf(k);
    for (Vector3r& point : x) point = R * point + k.translation;
  }
  fd.sourcePositions.insert(fd.sourcePositions.end(), x.begin(), x.end());
  fd.sourceVelocities.resize(fd.sourcePositions.size(), p.vector3("velocity"));
}

EmitterDescription parseEmitter(const json& e, const std::string& path, const LogSink& log) {
  Params p(e, path,
           {{"shape", ParamType::String, "rectangle", "nozzle shape", -std::numeric_limits<double>::infinity(),
             std::numeric_limits<double>::infinity(), {"rectangle", "circle"}},
            {"position", ParamType::Vector3, json(), "centre of the nozzle, m"},
            {"direction", ParamType::Vector3, json(), "emission direction (normalised)"},
            {"speed", ParamType::Real, json(), "emission speed, m/s", 1e-6, 1e4},
            {"width", ParamType::Real, 0.0, "rectangle: extent along the horizontal nozzle axis, m", 0, 1e6},
            {"height", ParamType::Real, 0.0, "rectangle: extent along the other nozzle axis, m", 0, 1e6},
            {"radius", ParamType::Real, 0.0, "circle: radius, m", 0, 1e6},
            {"start", ParamType::Real, 0.0, "time the first layer leaves the nozzle, s", 0, 1e9},
            {"end", ParamType::Real, 1e9, "time emission stops, s (the budget counts up to min(end, stopAt))", 0, 1e9}},
           log, {});
  EmitterDescription d;
  d.path = path;
  d.circle = p.string("shape") == "circle";
  d.position = p.vector3("position");
  d.direction = p.vector3("direction");
  if (d.direction.isZero(0)) throw InputError(p.pathOf("direction") + ": must not be the zero vector");
  d.direction.stableNormalize();  // normalize() overflows to zero on [1e200, 0, 0]
  d.speed = p.real("speed");
  d.width = p.real("width");
  d.height = p.real("height");
  d.radius = p.real("radius");
  d.start = p.real("start");
  d.end = p.real("end");
  if (d.circle && d.radius <= 0) throw InputError(p.pathOf("radius") + ": a circular nozzle needs a radius > 0");
  if (!d.circle && (d.width <= 0 || d.height <= 0))
    throw InputError(path + ": a rectangular nozzle needs \"width\" and \"height\" > 0");
  if (d.end <= d.start) throw InputError(p.pathOf("end") + ": must exceed start");
  return d;
}

// "auto" and the treatments' names, the choices simulation.boundaryPressure accepts.
std::vector<std::string> boundaryPressureChoices() {
  std::vector<std::string> names{"auto"};
  for (const auto& entry : kBoundaryPressureNames) names.push_back(entry.second);
  return names;
}

// "simulation": the step, the resolution and the plugins' choice (their parameters are read by
// the plugins themselves when the simulation is built).
void parseSimulationSection(const json& scene, const LogSink& log, SceneDescription& s) {
  const json& sim = child(scene, "", "simulation", "an object");
  if (!sim.is_null()) expectObject(sim, "simulation");
  Params sp(sim, "simulation",
            {{"particleRadius", ParamType::Real, 0.025, "particle radius r, m (kernel support 4r)", 1e-5, 10},
             {"gravity", ParamType::Vector3, json::array({0, -9.81, 0}), "gravitational acceleration, m/s^2"},
             {"cflFactor", ParamType::Real, 1.0, "dt = cflFactor 0.4 (2r) / max|v|", 1e-3, 10},
             {"timeStepControl", ParamType::String, "cfl",
              "cfl: the CFL step; iterations: the CFL step, also shrunk 10 % after a step whose density solve took more "
              "than 10 iterations and grown 10 % (up to the CFL step) after one that took fewer than 5 (SPlisHSPlasH's "
              "cflMethod 2)",
              -std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(), {"cfl", "iterations"}},
             {"minTimeStep", ParamType::Real, 1e-4, "lower bound of the adaptive time step, s", 1e-8, 1},
             {"maxTimeStep", ParamType::Real, kDefaultMaxTimeStep,
              "upper bound of the adaptive time step, s; when not given: min(0.005, CFL step at the scene's speed scale sqrt(v0^2 + 2 g H), 0.125 h^2 / nu of an explicit viscosity)",
              1e-8, 1},
             {"initialTimeStep", ParamType::Real, 0.001, "time step of the first step, s", 1e-8, 1},
             {"stopAt", ParamType::Real, 1.0, "simulated end time, s", 0, 1e9},
             {"particleSpacing", ParamType::Real, 1.8566, "lattice spacing of fluid blocks in particle radii r (particle volume = spacing^3); the default gives SPlisHSPlasH's volume 0.8 (2r)^3", 1.2, 3},
             {"sortInterval", ParamType::Int, 50, "re-sort particles in Z-order every this many steps (0: never)", 0, 1e9},
             {"maxParticles", ParamType::Real, 0.0,
              "refuse a scene whose estimated memory exceeds this many fluid particles' (2 KB each; boundary samples and "
              "volume-map cells count by their size); 0: half this machine's memory", 0, 1e15},
             {"iterationCapSteps", ParamType::Int, 100, "stop when the pressure solver hits its iteration cap this many steps in a row", 1, 1e9},
             {"boundaryPressure", ParamType::String, "auto",
              "boundary neighbours in the pressure solve (auto: extrapolation with sampled walls, consistent with volume maps)",
              -std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(), boundaryPressureChoices()}},
            log, {"pressureSolver", "boundaryModel", "domain"});
  s.particleRadius = sp.real("particleRadius");
  s.gravity = sp.vector3("gravity");
  s.cflFactor = sp.real("cflFactor");
  s.iterationFeedback = sp.string("timeStepControl") == "iterations";
  s.minTimeStep = sp.real("minTimeStep");
  s.maxTimeStep = sp.real("maxTimeStep");
  s.maxTimeStepGiven = sp.isSet("maxTimeStep");
  s.initialTimeStep = sp.real("initialTimeStep");
  if (s.minTimeStep > s.maxTimeStep) throw InputError("simulation.minTimeStep: must not exceed simulation.maxTimeStep");
  s.stopAt = sp.real("stopAt");
  s.particleSpacing = sp.real("particleSpacing");
  s.sortInterval = sp.integer("sortInterval");
  s.iterationCapSteps = sp.integer("iterationCapSteps");
  s.maxParticles = sp.real("maxParticles");
  const std::string bp = sp.string("boundaryPressure");
  s.boundaryPressureAuto = bp == "auto";
  s.boundaryPressure = BoundaryPressure::Consistent;  // "auto" is resolved when the boundary model is known
  for (const auto& [value, name] : kBoundaryPressureNames)
    if (bp == name) s.boundaryPressure = value;
  s.pressureSolver = child(sim, "simulation", "pressureSolver", "an object or a plugin name");
  if (s.pressureSolver.is_null()) s.pressureSolver = {{"type", "DFSPH"}};
  if (s.pressureSolver.is_string()) s.pressureSolver = {{"type", s.pressureSolver}};
  s.boundaryModel = child(sim, "simulation", "boundaryModel", "an object or a plugin name");
  if (s.boundaryModel.is_null()) s.boundaryModel = {{"type", "Akinci2012"}};
  if (s.boundaryModel.is_string()) s.boundaryModel = {{"type", s.boundaryModel}};
  for (auto* plugin : {&s.pressureSolver, &s.boundaryModel}) {
    const bool solver = plugin == &s.pressureSolver;
    const std::string path = solver ? "simulation.pressureSolver" : "simulation.boundaryModel";
    expectObject(*plugin, path);
    if (!plugin->contains("type")) (*plugin)["type"] = solver ? "DFSPH" : "Akinci2012";  // the documented defaults
    if (!(*plugin)["type"].is_string()) throw InputError(path + ".type: expected a string naming the plugin");
  }
  if (const json& d = child(sim, "simulation", "domain", "an object"); !d.is_null()) {
    Params dp(d, "simulation.domain",
              {{"min", ParamType::Vector3, json(), "lower corner, m"}, {"max", ParamType::Vector3, json(), "upper corner, m"}}, log, {});
    s.hasDomain = true;
    s.domainMin = dp.vector3("min");
    s.domainMax = dp.vector3("max");
    if ((s.domainMax - s.domainMin).minCoeff() <= 0) throw InputError("simulation.domain: max must exceed min on every axis");
  }
}

// fluids[].forces: objects with a "type", each type once (their parameters are the plugins').
json parseForceList(const json& fluid, const std::string& path) {
  json forces = child(fluid, path, "forces", "an array of force objects");
  if (forces.is_null()) forces = json::array();
  if (!forces.is_array()) throw InputError(path + ".forces: expected an array of force objects");
  for (std::size_t i = 0; i < forces.size(); ++i) {
    const std::string fpth = path + ".forces[" + std::to_string(i) + "]";
    expectObject(forces[i], fpth);
    if (!forces[i].contains("type") || !forces[i]["type"].is_string()) throw InputError(fpth + ".type: required string is missing");
    // One force of each type: a second instance would share the first's particle fields
    // (ParticleFields::add hands out the field of that name), each overwriting the other's state.
    const std::string type = forces[i]["type"].get<std::string>();
    for (std::size_t k = 0; k < i; ++k)
      if (lowerCase(forces[k]["type"].get<std::string>()) == lowerCase(type))
        throw InputError(fpth + ": a second " + type + " (" + path + ".forces[" + std::to_string(k) +
                         "] is one): give each force once, with the coefficients it needs");
  }
  return forces;
}

// fluids[].blocks[b], refused where it overlaps an earlier block of the same fluid.
FluidBlock parseBlock(const json& blockJson, const std::string& path, std::size_t b, const std::vector<FluidBlock>& earlier,
                      const LogSink& log) {
  const std::string bpth = path + ".blocks[" + std::to_string(b) + "]";
  Params bp2(blockJson, bpth,
             {{"min", ParamType::Vector3, json(), "lower corner, m"},
              {"max", ParamType::Vector3, json(), "upper corner, m"},
              {"velocity", ParamType::Vector3, json::array({0, 0, 0}), "initial velocity, m/s"},
              {"lattice", ParamType::String, "cellCentred",
               "lattice the block is filled on: cellCentred (particleSpacing r) or SPlisHSPlasH's denseMode 0, 1, 2 "
               "(splishsplashRegular: 2r grid, splishsplashMoreDense, splishsplashDense)",
               -std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
               std::vector<std::string>(blockLatticeNames().begin(), blockLatticeNames().end())}},
             log, {});
  FluidBlock block{bp2.vector3("min"), bp2.vector3("max"), bp2.vector3("velocity"), blockLatticeFromName(bp2.string("lattice"))};
  if ((block.max - block.min).minCoeff() <= 0) throw InputError(bpth + ": max must exceed min on every axis");
  for (std::size_t e = 0; e < earlier.size(); ++e)
    if ((block.max.cwiseMin(earlier[e].max) - block.min.cwiseMax(earlier[e].min)).minCoeff() > 0)
      throw InputError(bpth + ": overlaps " + path + ".blocks[" + std::to_string(e) + "]: their particles would lie on top of each other");
  return block;
}

// fluids[f]: its name and density, forces, emitters, removal box, particle files, mesh volumes and
// blocks (spacing and radius: the lattice the mesh volumes are filled on).
FluidDescription parseFluid(const json& fluid, const std::string& path, const std::string& baseDir, Real spacing, Real radius,
                            const LogSink& log) {
  expectObject(fluid, path);
  Params fp(fluid, path,
            {{"name", ParamType::String, "fluid", "name of the fluid (output files, Python)"},
             {"density0", ParamType::Real, 1000.0, "rest density rho0, kg/m^3", 1e-3, 1e6}},
            log, {"forces", "blocks", "emitters", "removeOutside", "particleFiles", "meshVolumes"});
  FluidDescription fd;
  fd.name = fp.string("name");
  checkFileName(fd.name, fp.pathOf("name"));
  fd.density0 = fp.real("density0");
  fd.path = path;
  fd.forces = parseForceList(fluid, path);
  const json& blocks = child(fluid, path, "blocks", "an array of blocks");
  const json& emitters = child(fluid, path, "emitters", "an array of emitters");
  if (!emitters.is_null() && !emitters.is_array()) throw InputError(path + ".emitters: expected an array of emitters");
  // Two equal sources (emitters, particle files, mesh volumes) or overlapping blocks would put
  // particles on top of each other: the fluid would start at twice its rest density there.
  auto checkDistinct = [&](const json& list, std::size_t i, const std::string& key) {
    if (const std::size_t k = earlierEqual(list, i); k != std::string::npos)
      throw InputError(path + "." + key + "[" + std::to_string(i) + "]: the same as " + path + "." + key + "[" + std::to_string(k) +
                       "]: their particles would lie on top of each other");
  };
  for (std::size_t e = 0; e < emitters.size(); ++e) {
    fd.emitters.push_back(parseEmitter(emitters[e], path + ".emitters[" + std::to_string(e) + "]", log));
    checkDistinct(emitters, e, "emitters");
  }
  if (const json& ro = child(fluid, path, "removeOutside", "an object"); !ro.is_null()) {
    Params rp(ro, path + ".removeOutside",
              {{"min", ParamType::Vector3, json(), "lower corner, m"}, {"max", ParamType::Vector3, json(), "upper corner, m"}}, log, {});
    fd.removeOutside = true;
    fd.removeMin = rp.vector3("min");
    fd.removeMax = rp.vector3("max");
    if ((fd.removeMax - fd.removeMin).minCoeff() <= 0) throw InputError(path + ".removeOutside: max must exceed min on every axis");
  }
  for (const char* key : {"particleFiles", "meshVolumes"}) {
    const json& list = child(fluid, path, key, "an array");
    if (!list.is_null() && !list.is_array()) throw InputError(path + "." + key + ": expected an array");
    for (std::size_t i = 0; i < list.size(); ++i) {
      const std::string ipath = path + "." + key + "[" + std::to_string(i) + "]";
      if (std::string(key) == "particleFiles") parseParticleFile(list[i], ipath, baseDir, log, fd);
      else parseMeshVolume(list[i], ipath, baseDir, spacing, radius, log, fd);
      checkDistinct(list, i, key);
    }
  }
  if (!blocks.is_null() && !blocks.is_array()) throw InputError(path + ".blocks: expected an array of blocks");
  if (blocks.empty() && fd.emitters.empty() && fd.sourcePositions.empty())
    throw InputError(path + ".blocks: expected a non-empty array of blocks (or emitters, particleFiles, meshVolumes)");
  for (std::size_t b = 0; b < blocks.size(); ++b) fd.blocks.push_back(parseBlock(blocks[b], path, b, fd.blocks, log));
  return fd;
}

void parseFluids(const json& scene, const std::string& baseDir, const LogSink& log, SceneDescription& s) {
  const json& fluids = child(scene, "", "fluids", "a non-empty array of fluids");
  if (!fluids.is_array() || fluids.empty()) throw InputError("fluids: expected a non-empty array of fluids");
  if (fluids.size() > 1) throw InputError("fluids: only one fluid per scene is supported in this version");
  for (std::size_t f = 0; f < fluids.size(); ++f)
    s.fluids.push_back(parseFluid(fluids[f], "fluids[" + std::to_string(f) + "]", baseDir, s.particleSpacing * s.particleRadius,
                                  s.particleRadius, log));
}

// "boundaries": each object, with the names force probes and bodies.csv tell them by unique.
void parseBoundaries(const json& scene, const std::string& baseDir, const LogSink& log, SceneDescription& s) {
  const json& boundaries = child(scene, "", "boundaries", "an array");
  if (!boundaries.is_null() && !boundaries.is_array()) throw InputError("boundaries: expected an array");
  for (std::size_t b = 0; b < boundaries.size(); ++b) {
    const std::string path = "boundaries[" + std::to_string(b) + "]";
    s.boundaries.push_back(parseBoundary(boundaries[b], path, baseDir, log));
    // Force probes and bodies.csv tell objects by name; the same object twice is coincident walls
    // or bodies.
    const std::string& name = s.boundaries[b].name;
    for (std::size_t e = 0; e < b && !name.empty(); ++e)
      if (s.boundaries[e].name == name)
        throw InputError(path + ".name: '" + name + "' already names boundaries[" + std::to_string(e) +
                         "] (force probes and bodies.csv tell objects by name)");
    if (const std::size_t e = earlierEqual(boundaries, b, "name"); e != std::string::npos)
      throw InputError(path + ": the same object as boundaries[" + std::to_string(e) + "] (equal but for the name): coincident walls or bodies");
  }

}

// "output": frames, probes.csv's rate, checkpoints and the particle fields written.
OutputSettings parseOutput(const json& scene, const LogSink& log) {
  OutputSettings output;
  const json& out = child(scene, "", "output", "an object");
  constexpr double inf = std::numeric_limits<double>::infinity();
  Params op(out, "output",
            {{"enabled", ParamType::Bool, true, "write frames"},
             {"directory", ParamType::String, "output", "output folder (relative to the working directory)"},
             {"fps", ParamType::Real, 25.0, "frames per simulated second", 1e-3, 1e6},
             {"probeFps", ParamType::Real, 0.0, "rows of probes.csv per simulated second (0: one per step)", 0, 1e9},
             {"overwrite", ParamType::Bool, false, "clear another run's files (frames, .pvd, ...) from the folder instead of refusing it"},
             {"format", ParamType::String, "vtu", "frame files: vtu (ParaView), bgeo (Houdini, .bgeo.gz), ply (Blender)", -inf, inf,
              {"vtu", "bgeo", "ply"}},
             {"precision", ParamType::String, "float", "floating-point values in frames: float (float32) or double", -inf, inf,
              {"float", "double"}},
             {"bodies", ParamType::String, "auto", "moving bodies per frame: meshes, transforms (one point per body) or auto "
              "(transforms for bgeo, meshes otherwise)", -inf, inf, {"auto", "meshes", "transforms"}},
             {"checkpointInterval", ParamType::Real, 0.0, "simulated seconds between checkpoints (0: none)", 0, 1e9}},
            log, {"attributes"});
  output.enabled = op.boolean("enabled");
  output.directory = op.string("directory");
  if (output.directory.empty() || !printableUtf8(output.directory))
    throw InputError("output.directory: must name a folder (non-empty printable UTF-8 text)");
  output.fps = op.real("fps");
  output.probeFps = op.real("probeFps");
  output.overwrite = op.boolean("overwrite");
  output.format = frameFormatFromName(op.string("format"));
  output.precision = op.string("precision") == "double" ? FramePrecision::Double : FramePrecision::Float;
  const std::string bodies = op.string("bodies");
  output.bodies = bodies == "meshes" || (bodies == "auto" && output.format != FrameFormat::Bgeo) ? BodyFrames::Meshes
                                                                                                   : BodyFrames::Transforms;
  if (output.format == FrameFormat::Bgeo && output.precision == FramePrecision::Double)
    throw InputError("output.precision: \"double\" is not available with \"format\": \"bgeo\" (classic BGEO stores float32 only)");
  if (output.format == FrameFormat::Bgeo && output.bodies == BodyFrames::Meshes)
    throw InputError("output.bodies: \"meshes\" is not available with \"format\": \"bgeo\" (points only); use \"transforms\"");
  output.checkpointInterval = op.real("checkpointInterval");
  // The fields are registered when the simulation is built: it checks the names (checkAttributes).
  if (out.is_object() && out.contains("attributes")) {
    const json& a = out["attributes"];
    if (!a.is_array()) throw InputError("output.attributes: expected an array of particle field names");
    for (std::size_t i = 0; i < a.size(); ++i) {
      if (!a[i].is_string()) throw InputError("output.attributes[" + std::to_string(i) + "]: expected a particle field name (a string)");
      output.attributes.push_back(a[i].get<std::string>());
    }
  }
  return output;
}

}  // namespace

SceneDescription parseScene(const json& scene, const std::string& baseDir, const LogSink& log) {
  if (!scene.is_object()) throw InputError("scene: expected a JSON object at the top level");
  SceneDescription s;
  s.raw = scene;
  s.baseDir = baseDir;
  Params top(scene, "",
             {{"name", ParamType::String, "", "name of the scene (the summary's \"scene\")"},
              {"description", ParamType::String, "", "free text"}},
             log, {"simulation", "fluids", "boundaries", "probes", "output"});
  parseSimulationSection(scene, log, s);
  parseFluids(scene, baseDir, log, s);
  parseBoundaries(scene, baseDir, log, s);
  s.output = parseOutput(scene, log);
  // probes (resolved against the boundaries when the simulation is built)
  s.probes = parseProbes(child(scene, "", "probes", "an array of probe objects"), log);
  return s;
}

SceneDescription loadSceneFile(const std::string& path, const std::vector<std::pair<std::string, std::string>>& overrides,
                               const LogSink& log) {
  json scene = readJsonFile(path);
  const std::string dir = std::filesystem::path(path).parent_path().string();
  // A SPlisHSPlasH scene runs as the consph scene it maps to; --set addresses that scene's keys.
  const bool splishsplash = isSplishSplashScene(scene);
  if (splishsplash) {
    if (log) log(LogLevel::Info, path + ": a SPlisHSPlasH scene, run as the consph scene it maps to (docs/splishsplash.md; consph convert writes it out)");
    try {
      scene = convertSplishSplashScene(scene, dir, dir, std::filesystem::path(path).stem().string(), log);
    } catch (const InputError& e) {
      throw InputError(path + ": " + e.what());
    }
  }
  for (auto& [key, value] : overrides) applyOverride(scene, key, value);
  if (!splishsplash) return namingSceneFile(path, [&] { return parseScene(scene, dir, log); });
  try {
    return parseScene(scene, dir, log);
  } catch (const InputError& e) {
    throw InputError(path + " (as the consph scene it maps to, see consph convert): " + e.what());
  }
}

}  // namespace consph
