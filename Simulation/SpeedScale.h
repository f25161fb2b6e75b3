// The largest speed a scene's physics can give it, from its start state alone:
//   U = sqrt(v0^2 + 2 |g| H),
// v0 the fastest initial or prescribed speed (fluid blocks, emitters, moving bodies' surface
// points, hinge motors' targets), H the height from the highest fluid, emitter or moving body
// down to the lowest static boundary or fluid (along g). Energy: nothing driven by gravity alone
// falls faster than that. sqrt(2 g H) is the speed scale of a free-surface flow in
//   J. J. Monaghan: Simulating free surface flows with SPH. Journal of Computational Physics
//   110(2), 1994, 399-406
// (its weakly compressible sound speed is ten of them). Used to bound the adaptive time step
// and to tell a blown-up body from a fast one.
#pragma once
#include "Simulation/Scene.h"

namespace consph {

struct SpeedScale {
  Real speed = 0;          // U, m/s
  Real fallHeight = 0;     // H, m
  Real initialSpeed = 0;   // v0, m/s
};

SpeedScale sceneSpeedScale(const SceneDescription& scene);

}  // namespace consph
