// The one test of a point against an axis-aligned box [lo, hi], faces included, that force-probe
// regions, fluid removal boxes, the volume maps' load split, the domain checks and the start-up
// test for fluid inside bodies share. A non-finite point is outside.
#pragma once
#include "Utilities/Types.h"

namespace consph {

inline bool insideBox(const Vector3r& p, const Vector3r& lo, const Vector3r& hi) {
  return (p - lo).minCoeff() >= 0 && (hi - p).minCoeff() >= 0;
}

}  // namespace consph
