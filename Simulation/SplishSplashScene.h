// SPlisHSPlasH scene files (its Configuration / Materials / FluidBlocks / FluidModels /
// RigidBodies / Emitters / AnimationFields layout, 2.16's namespaced method blocks and the older
// flat keys) mapped to the consph scene that runs the same simulation. Each SPlisHSPlasH key
// consph cannot honour is warned once, naming it and every place it appears; the mapping, key by
// key, is docs/splishsplash.md.
#pragma once
#include <string>

#include "Simulation/Params.h"
#include "Utilities/Log.h"

namespace consph {

// True when `scene` is laid out as a SPlisHSPlasH scene: it has one of SPlisHSPlasH's top-level
// keys and no consph "fluids".
bool isSplishSplashScene(const json& scene);

// The consph scene equivalent to the SPlisHSPlasH scene `scene`, named `name`. Relative file names
// in `scene` are relative to `sceneDir` (as SPlisHSPlasH reads them); in the result they are
// relative to `targetDir`, the folder the consph scene is written to (or `sceneDir` itself).
// Throws InputError naming the JSON path for a value of the wrong type or one no consph scene can
// express (a 2D scene, two fluids, an unknown method id).
json convertSplishSplashScene(const json& scene, const std::string& sceneDir, const std::string& targetDir,
                              const std::string& name, const LogSink& log);

}  // namespace consph
