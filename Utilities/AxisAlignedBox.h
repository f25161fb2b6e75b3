// The one test of a point against an axis-aligned box [lo, hi], faces included, that force-probe
// regions, fluid removal boxes, the volume maps' load split, the domain checks and the start-up
// test for fluid inside bodies share. A non-finite point is outside. And the one bounding box of a
// point set, in parallel, that the neighbour search's grid and DFSPH's packed slots share.
#pragma once
#include <cstddef>

#include "Utilities/ParallelFor.h"
#include "Utilities/Types.h"

namespace consph {

inline bool insideBox(const Vector3r& p, const Vector3r& lo, const Vector3r& hi) {
  return (p - lo).minCoeff() >= 0 && (hi - p).minCoeff() >= 0;
}

// The bounding box of points[0 .. n) (n >= 1), and whether every point is finite (min and max
// skip a NaN, so each point is checked).
struct PointBox {
  Vector3r lo, hi;
  bool finite;
};
inline PointBox boxOfPoints(const Vector3r* points, std::size_t n) {
  return parallelReduce(
      n, PointBox{points[0], points[0], true},
      [](PointBox& into, const PointBox& from) {
        into.lo = into.lo.cwiseMin(from.lo), into.hi = into.hi.cwiseMax(from.hi), into.finite = into.finite && from.finite;
      },
      [&](std::size_t i, PointBox& b) {
        b.finite = b.finite && points[i].allFinite();
        b.lo = b.lo.cwiseMin(points[i]);
        b.hi = b.hi.cwiseMax(points[i]);
      });
}

}  // namespace consph
