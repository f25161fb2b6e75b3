// The scene file: JSON parsed into plain data first, objects built second (pbrt's way).
// Every key is documented in docs/scene-format.md.
#pragma once
#include <string>
#include <vector>

#include "Simulation/BoundaryModel.h"
#include "Simulation/Emitter.h"
#include "Simulation/FluidBlock.h"
#include "Simulation/FrameFormat.h"
#include "Simulation/Params.h"
#include "Simulation/Probes.h"
#include "Simulation/StepContext.h"
#include "Utilities/PointTable.h"

namespace consph {

struct FluidDescription {
  std::string name;
  Real density0;     // rest density rho0, kg/m^3
  json forces;       // array of plugin objects, applied in this order
  std::string path;  // JSON path of this fluid, for messages
  std::vector<FluidBlock> blocks;
  // Particles from point files and closed meshes' volumes (particleFiles, meshVolumes), in
  // world space, with their initial velocities.
  std::vector<Vector3r> sourcePositions, sourceVelocities;
  std::vector<EmitterDescription> emitters;
  bool removeOutside = false;  // particles outside [removeMin, removeMax] are removed
  Vector3r removeMin = Vector3r::Zero(), removeMax = Vector3r::Zero();
};

struct OutputSettings {
  bool enabled = true;
  std::string directory = "output";
  Real fps = 25;
  Real probeFps = 0;  // probe rows per simulated second; 0: every step
  bool overwrite = false;  // clear another run's files from the folder instead of refusing it
  FrameFormat format = FrameFormat::Vtu;
  std::vector<std::string> attributes;  // particle fields in each frame; empty: the exported ones
  FramePrecision precision = FramePrecision::Float;
  BodyFrames bodies = BodyFrames::Meshes;  // moving bodies per frame (BGEO: transforms)
  Real checkpointInterval = 0;             // simulated seconds between checkpoints; 0: none
};

// simulation.maxTimeStep's default, s: the cap's constant part (Simulation::chooseTimeStepCap).
inline constexpr double kDefaultMaxTimeStep = 0.005;

struct SceneDescription {
  json raw;             // the whole scene after overrides
  std::string baseDir;  // relative mesh paths are resolved against the scene's folder

  Real particleRadius = Real(0.025);
  Vector3r gravity = Vector3r(0, Real(-9.81), 0);
  Real cflFactor = 1, minTimeStep = Real(1e-4), maxTimeStep = Real(kDefaultMaxTimeStep), initialTimeStep = Real(0.001);
  // Given in the scene: then maxTimeStep is the cap as it stands; otherwise the cap is
  // min(maxTimeStep, the resolution's and the physics' bounds; Simulation's timeStepCap).
  bool maxTimeStepGiven = false;
  // "iterations": the CFL step, also shrunk 10 % after a step whose density solve took more than
  // 10 iterations and grown 10 % (never beyond the CFL step) after one that took fewer than 5.
  bool iterationFeedback = false;
  Real stopAt = 1;
  Real particleSpacing = Real(1.8566);  // lattice spacing of fluid blocks, in particle radii (0.8^(1/3) 2)
  int sortInterval = 50;
  int iterationCapSteps = 100;
  double maxParticles = 0;  // refuse scenes estimated above this many fluid particles' memory (0: half the machine's)  // stop when the solver hit its cap this many steps in a row
  BoundaryPressure boundaryPressure = BoundaryPressure::Consistent;
  // "auto" (the default): chosen by the boundary model when the simulation is built,
  // extrapolation for sampled walls, consistent for implicit ones (docs/boundary-pressure.md).
  bool boundaryPressureAuto = true;
  json pressureSolver;  // {"type": ..., params}
  json boundaryModel;   // {"type": ..., params}
  bool hasDomain = false;
  Vector3r domainMin = Vector3r::Zero(), domainMax = Vector3r::Zero();

  std::vector<FluidDescription> fluids;
  std::vector<BoundaryObject> boundaries;
  std::vector<ProbeDescription> probes;
  OutputSettings output;
  // A run option, not part of the scene file: the checkpoint the simulation continues from
  // (consph --restart FILE); empty: it starts at t = 0.
  std::string restartFrom;
};

// Reads a JSON file; malformed JSON -> InputError "FILE:LINE:COLUMN: ...".
json readJsonFile(const std::string& path);

// Sets the value at a dotted path ("simulation.pressureSolver.maxError", array items by index:
// "fluids.0.density0"). `valueText` is parsed as JSON, or taken as a string when it is not JSON.
void applyOverride(json& scene, const std::string& dottedPath, const std::string& valueText);

SceneDescription parseScene(const json& scene, const std::string& baseDir, const LogSink& log);
SceneDescription loadSceneFile(const std::string& path, const std::vector<std::pair<std::string, std::string>>& overrides,
                               const LogSink& log);

}  // namespace consph
