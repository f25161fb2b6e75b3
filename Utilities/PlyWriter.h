// Binary little-endian PLY (Stanford polygon format, version 1.0), as Blender imports it: an
// ASCII header ("ply", "format binary_little_endian 1.0", "element vertex N" with one "property
// TYPE NAME" per value, "element face M" with "property list uchar int vertex_indices",
// "end_header"), then the vertices' values in header order and the faces. Vertices carry x y z
// and every column (a vector column NAME as NAME_x NAME_y NAME_z [NAME_w]).
#pragma once
#include <string>

#include "Utilities/PointTable.h"

namespace consph {

// The .ply bytes of `table`: float32 or float64 values, uint32 for integer columns; the
// triangles as faces when the table has them.
std::string serializePly(const PointTable& table, FramePrecision precision);

}  // namespace consph
