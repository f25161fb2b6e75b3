#include "Utilities/BgeoWriter.h"

#include <bit>
#include <cstdint>
#include <cstring>
#include <stdexcept>

namespace consph {

namespace {
// Appends big-endian values, whatever the machine's byte order.
class BigEndian {
 public:
  explicit BigEndian(std::string& out) : out_(out) {}
  void u16(std::uint16_t v) { bytes(v); }
  void i32(std::int32_t v) { bytes(std::uint32_t(v)); }
  void f32(float v) { bytes(std::bit_cast<std::uint32_t>(v)); }
  void text(const std::string& s) { out_.append(s); }

 private:
  template <class U>
  void bytes(U v) {
    for (int shift = int(8 * sizeof(U)) - 8; shift >= 0; shift -= 8) out_.push_back(char((v >> shift) & 0xff));
  }
  std::string& out_;
};
}  // namespace

std::string serializeBgeo(const PointTable& table) {
  if (table.triangles) throw std::invalid_argument("bgeo: triangle meshes are not written (points only)");
  std::string out;
  std::size_t valuesPerPoint = 4;
  for (const PointColumn& c : table.columns) valuesPerPoint += std::size_t(c.components);
  out.reserve(64 + 32 * table.columns.size() + 4 * valuesPerPoint * table.size);
  BigEndian be(out);
  be.text("BgeoV");
  be.i32(5);                                                        // version
  be.i32(std::int32_t(table.size));                                 // points
  for (int i = 0; i < 3; ++i) be.i32(0);                            // primitives, point groups, primitive groups
  be.i32(std::int32_t(table.columns.size()));                       // point attributes
  for (int i = 0; i < 3; ++i) be.i32(0);                            // vertex, primitive, detail attributes
  for (const PointColumn& c : table.columns) {
    be.u16(std::uint16_t(c.name.size()));
    be.text(c.name);
    be.u16(std::uint16_t(c.components));
    be.i32(c.integer ? 1 : c.components == 3 ? 5 : 0);
    for (int k = 0; k < c.components; ++k) be.i32(0);  // defaults
  }
  for (std::size_t i = 0; i < table.size; ++i) {
    const Vector3r& x = table.positions[i];
    be.f32(float(x[0])), be.f32(float(x[1])), be.f32(float(x[2])), be.f32(1.0f);  // homogeneous w
    for (const PointColumn& c : table.columns) {
      if (c.integer) be.i32(std::int32_t(table.index(c, i)));
      else
        for (int k = 0; k < c.components; ++k) be.f32(float(table.real(c, i, k)));
    }
  }
  out.push_back(char(0x00));
  out.push_back(char(0xff));
  return out;
}

}  // namespace consph
