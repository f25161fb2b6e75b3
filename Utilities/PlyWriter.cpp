#include "Utilities/PlyWriter.h"

#include <bit>
#include <cstdint>

namespace consph {

namespace {
// Appends little-endian values, whatever the machine's byte order.
template <class U>
void littleEndian(std::string& out, U v) {
  for (std::size_t b = 0; b < sizeof(U); ++b) out.push_back(char((v >> (8 * b)) & 0xff));
}
}  // namespace

std::string serializePly(const PointTable& table, FramePrecision precision) {
  const bool dbl = precision == FramePrecision::Double;
  const std::string type = dbl ? "double" : "float";
  std::string header = "ply\nformat binary_little_endian 1.0\ncomment consph frame\nelement vertex " + std::to_string(table.size) + "\n";
  for (const char* axis : {"x", "y", "z"}) header += "property " + type + " " + axis + "\n";
  static const char* const suffix[] = {"_x", "_y", "_z", "_w"};
  std::size_t valuesPerPoint = 3;
  for (const PointColumn& c : table.columns) {
    valuesPerPoint += std::size_t(c.components);
    if (c.integer) header += "property uint " + c.name + "\n";
    else if (c.components == 1) header += "property " + type + " " + c.name + "\n";
    else
      for (int k = 0; k < c.components; ++k) header += "property " + type + " " + c.name + suffix[k] + "\n";
  }
  if (table.triangles) header += "element face " + std::to_string(table.triangleCount) + "\nproperty list uchar int vertex_indices\n";
  header += "end_header\n";

  std::string out = std::move(header);
  out.reserve(out.size() + valuesPerPoint * (dbl ? 8 : 4) * table.size + 13 * table.triangleCount);
  auto real = [&](double v) {
    if (dbl) littleEndian(out, std::bit_cast<std::uint64_t>(v));
    else littleEndian(out, std::bit_cast<std::uint32_t>(float(v)));
  };
  for (std::size_t i = 0; i < table.size; ++i) {
    const Vector3r& x = table.positions[i];
    real(double(x[0])), real(double(x[1])), real(double(x[2]));
    for (const PointColumn& c : table.columns) {
      if (c.integer) littleEndian(out, std::uint32_t(table.index(c, i)));
      else
        for (int k = 0; k < c.components; ++k) real(table.real(c, i, k));
    }
  }
  for (std::size_t t = 0; t < table.triangleCount; ++t) {
    out.push_back(char(3));
    for (Index v : table.triangles[t]) littleEndian(out, std::uint32_t(v));
  }
  return out;
}

}  // namespace consph
