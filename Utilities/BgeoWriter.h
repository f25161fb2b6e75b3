// Houdini's classic binary geometry (.bgeo, version 5), as Houdini and partio read it: a
// big-endian header (magic "Bgeo", 'V', version 5, then the counts of points, primitives, point
// groups, primitive groups, point, vertex, primitive and detail attributes as int32), one
// definition per point attribute (uint16 name length, name, uint16 component count, int32 type:
// 0 float, 1 int, 5 vector; one int32 default per component), then per point x y z w as float32
// and its attributes' components, 4 bytes each, and the end-of-file bytes 0x00 0xff. Points
// only (no primitives): a particle cloud. Values are float32: the format has no double.
#pragma once
#include <string>

#include "Utilities/PointTable.h"

namespace consph {

// The .bgeo bytes of `table` (uncompressed; gzipCompress them for .bgeo.gz). 3-component Real
// columns are written as vectors (type 5), 1- and 4-component ones as floats, integer columns
// as int32. A table with triangles is refused (std::invalid_argument): polygons are not written.
std::string serializeBgeo(const PointTable& table);

}  // namespace consph
