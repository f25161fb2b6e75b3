// Particle positions (and velocities, where the file has them) read from a point file, to start
// a fluid from particles another tool made:
//   .ply   ASCII or binary (either byte order), the "vertex" element's x, y, z (vx, vy, vz);
//   .vtu   as consph writes its frames (appended raw data), the points and "velocity";
//   .bgeo  Houdini's classic geometry as partio writes it (gzip-compressed or not), the points
//          and the "v" attribute.
#pragma once
#include <string>
#include <vector>

#include "Utilities/Types.h"

namespace consph {

struct PointFile {
  std::vector<Vector3r> positions;   // m
  std::vector<Vector3r> velocities;  // m/s, one per position; empty when the file has none
};

// Throws InputError "PATH: ..." for a file that cannot be read or is not one of the formats.
PointFile readPointFile(const std::string& path);

}  // namespace consph
