#include "Utilities/PointFile.h"

#include <zlib.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "Utilities/Error.h"

namespace consph {

namespace {

std::string readWholeFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open the point file");
  std::stringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

// The bytes of a gzip file, or `bytes` itself when they are not gzip-compressed.
std::string gunzip(const std::string& bytes, const std::string& path) {
  if (bytes.size() < 2 || static_cast<unsigned char>(bytes[0]) != 0x1f || static_cast<unsigned char>(bytes[1]) != 0x8b) return bytes;
  z_stream z{};
  if (inflateInit2(&z, 16 + MAX_WBITS) != Z_OK) throw InputError(path + ": cannot start gzip decompression");
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(bytes.data()));
  z.avail_in = uInt(bytes.size());
  std::string out;
  char chunk[1 << 16];
  int status = Z_OK;
  while (status != Z_STREAM_END) {
    z.next_out = reinterpret_cast<Bytef*>(chunk);
    z.avail_out = sizeof(chunk);
    status = inflate(&z, Z_NO_FLUSH);
    if (status != Z_OK && status != Z_STREAM_END) {
      inflateEnd(&z);
      throw InputError(path + ": corrupt gzip data");
    }
    out.append(chunk, sizeof(chunk) - z.avail_out);
  }
  inflateEnd(&z);
  return out;
}

// Reads numbers of either byte order from a byte string, with bounds checks.
class ByteReader {
 public:
  ByteReader(const std::string& bytes, std::size_t at, bool bigEndian, std::string path)
      : bytes_(bytes), at_(at), bigEndian_(bigEndian), path_(std::move(path)) {}

  template <class T>
  T read() {
    if (at_ + sizeof(T) > bytes_.size()) throw InputError(path_ + ": the file ends early (truncated?)");
    unsigned char raw[sizeof(T)];
    std::memcpy(raw, bytes_.data() + at_, sizeof(T));
    at_ += sizeof(T);
    if (bigEndian_ != (std::endian::native == std::endian::big)) std::reverse(raw, raw + sizeof(T));
    T value;
    std::memcpy(&value, raw, sizeof(T));
    return value;
  }
  void skip(std::size_t n) {
    if (at_ + n > bytes_.size()) throw InputError(path_ + ": the file ends early (truncated?)");
    at_ += n;
  }
  std::string text(std::size_t n) {
    skip(n);
    return bytes_.substr(at_ - n, n);
  }

 private:
  const std::string& bytes_;
  std::size_t at_;
  bool bigEndian_;
  std::string path_;
};

// ---- PLY (Turk 1994; the header names each element and its typed properties) ----

struct PlyProperty {
  std::string name, type, countType;  // countType: a list's count type, empty for a scalar
};
struct PlyElement {
  std::string name;
  std::size_t count = 0;
  std::vector<PlyProperty> properties;
};

std::size_t plySize(const std::string& type, const std::string& path) {
  static const std::map<std::string, std::size_t> sizes = {
      {"char", 1},  {"uchar", 1}, {"int8", 1},  {"uint8", 1},  {"short", 2},   {"ushort", 2},  {"int16", 2},
      {"uint16", 2}, {"int", 4},  {"uint", 4},  {"int32", 4},  {"uint32", 4},  {"float", 4},   {"float32", 4},
      {"double", 8}, {"float64", 8}};
  auto it = sizes.find(type);
  if (it == sizes.end()) throw InputError(path + ": PLY property type '" + type + "' is not a PLY type");
  return it->second;
}

double plyValue(ByteReader& in, const std::string& type) {
  if (type == "char" || type == "int8") return in.read<std::int8_t>();
  if (type == "uchar" || type == "uint8") return in.read<std::uint8_t>();
  if (type == "short" || type == "int16") return in.read<std::int16_t>();
  if (type == "ushort" || type == "uint16") return in.read<std::uint16_t>();
  if (type == "int" || type == "int32") return in.read<std::int32_t>();
  if (type == "uint" || type == "uint32") return in.read<std::uint32_t>();
  if (type == "float" || type == "float32") return in.read<float>();
  return in.read<double>();
}

PointFile readPly(const std::string& bytes, const std::string& path) {
  const std::size_t end = bytes.find("end_header");
  if (bytes.rfind("ply", 0) != 0 || end == std::string::npos) throw InputError(path + ": not a PLY file (no 'ply' ... 'end_header')");
  std::istringstream header(bytes.substr(0, end));
  std::string line, format;
  std::vector<PlyElement> elements;
  while (std::getline(header, line)) {
    std::istringstream words(line);
    std::string word;
    words >> word;
    if (word == "format") {
      words >> format;
    } else if (word == "element") {
      PlyElement e;
      words >> e.name >> e.count;
      elements.push_back(e);
    } else if (word == "property") {
      if (elements.empty()) throw InputError(path + ": PLY property before any element");
      PlyProperty p;
      words >> p.type;
      if (p.type == "list") words >> p.countType >> p.type;
      words >> p.name;
      plySize(p.type, path);
      if (!p.countType.empty()) plySize(p.countType, path);
      elements.back().properties.push_back(p);
    }
  }
  if (format != "ascii" && format != "binary_little_endian" && format != "binary_big_endian")
    throw InputError(path + ": PLY format '" + format + "' is not ascii, binary_little_endian or binary_big_endian");
  std::size_t data = bytes.find('\n', end);
  data = data == std::string::npos ? bytes.size() : data + 1;

  PointFile points;
  bool found = false;
  std::istringstream ascii(format == "ascii" ? bytes.substr(data) : std::string());
  ByteReader binary(bytes, data, format == "binary_big_endian", path);
  for (const PlyElement& e : elements) {
    const bool vertex = e.name == "vertex";
    int slot[6] = {-1, -1, -1, -1, -1, -1};  // x y z vx vy vz
    // Velocities as vx vy vz, or as consph's own PLY frames name them (velocity_x ...), so a
    // frame can start the next run.
    const char* names[6] = {"x", "y", "z", "vx", "vy", "vz"};
    const char* frameNames[6] = {"x", "y", "z", "velocity_x", "velocity_y", "velocity_z"};
    for (std::size_t p = 0; p < e.properties.size(); ++p)
      for (int s = 0; s < 6; ++s)
        if ((e.properties[p].name == names[s] || e.properties[p].name == frameNames[s]) && e.properties[p].countType.empty())
          slot[s] = int(p);
    if (vertex) {
      if (slot[0] < 0 || slot[1] < 0 || slot[2] < 0) throw InputError(path + ": the PLY vertex element has no x, y, z");
      found = true;
      points.positions.resize(e.count);
    }
    const bool velocity = vertex && slot[3] >= 0 && slot[4] >= 0 && slot[5] >= 0;
    if (velocity) points.velocities.resize(e.count);
    std::vector<double> values(e.properties.size());
    for (std::size_t i = 0; i < e.count; ++i) {
      for (std::size_t p = 0; p < e.properties.size(); ++p) {
        const PlyProperty& prop = e.properties[p];
        if (format == "ascii") {
          double count = 1;
          if (!prop.countType.empty() && !(ascii >> count)) throw InputError(path + ": the PLY data ends early");
          for (long k = 0; k < long(count); ++k)
            if (!(ascii >> values[p])) throw InputError(path + ": the PLY data ends early or is not a number");
        } else if (!prop.countType.empty()) {
          const double count = plyValue(binary, prop.countType);
          binary.skip(std::size_t(count) * plySize(prop.type, path));
        } else {
          values[p] = plyValue(binary, prop.type);
        }
      }
      if (vertex) {
        points.positions[i] = Vector3r(Real(values[std::size_t(slot[0])]), Real(values[std::size_t(slot[1])]), Real(values[std::size_t(slot[2])]));
        if (velocity)
          points.velocities[i] = Vector3r(Real(values[std::size_t(slot[3])]), Real(values[std::size_t(slot[4])]), Real(values[std::size_t(slot[5])]));
      }
    }
    if (vertex) break;  // what follows (faces) is not needed
  }
  if (!found) throw InputError(path + ": the PLY file has no vertex element");
  return points;
}

// ---- VTU, as consph writes it (Utilities/VtkWriter.cpp): appended raw data, UInt64 headers ----

// The value of attribute `name` in the XML tag that starts at `tag`.
std::string attribute(const std::string& xml, std::size_t tag, const std::string& name) {
  const std::size_t close = xml.find('>', tag);
  const std::size_t at = xml.find(" " + name + "=\"", tag);
  if (at == std::string::npos || at > close) return "";
  const std::size_t start = at + name.size() + 3;
  return xml.substr(start, xml.find('"', start) - start);
}

std::vector<Vector3r> vtuVectors(const std::string& bytes, std::size_t tag, std::size_t base, std::size_t n, bool header64,
                                 const std::string& path) {
  const std::string type = attribute(bytes, tag, "type"), offset = attribute(bytes, tag, "offset");
  const std::string components = attribute(bytes, tag, "NumberOfComponents");
  if (attribute(bytes, tag, "format") != "appended" || offset.empty())
    throw InputError(path + ": only .vtu files with appended raw data (as consph writes them) are read");
  if (components != "3") throw InputError(path + ": a vector array does not have 3 components");
  if (type != "Float64" && type != "Float32") throw InputError(path + ": vector arrays of type '" + type + "' are not read");
  ByteReader in(bytes, base + std::stoull(offset), false, path);
  const std::uint64_t size = header64 ? in.read<std::uint64_t>() : in.read<std::uint32_t>();
  const std::size_t scalar = type == "Float64" ? 8 : 4;
  if (size != n * 3 * scalar) throw InputError(path + ": an array's size does not match NumberOfPoints");
  std::vector<Vector3r> v(n);
  for (auto& x : v)
    for (int c = 0; c < 3; ++c) x[c] = Real(scalar == 8 ? in.read<double>() : in.read<float>());
  return v;
}

PointFile readVtu(const std::string& bytes, const std::string& path) {
  const std::size_t piece = bytes.find("<Piece");
  const std::size_t appended = bytes.find("<AppendedData");
  if (bytes.find("<VTKFile") == std::string::npos || piece == std::string::npos || appended == std::string::npos)
    throw InputError(path + ": not a .vtu file with appended data");
  if (attribute(bytes, bytes.find("<VTKFile"), "byte_order") != "LittleEndian") throw InputError(path + ": only little-endian .vtu files are read");
  if (attribute(bytes, appended, "encoding") != "raw") throw InputError(path + ": only raw appended data is read (not base64)");
  const bool header64 = attribute(bytes, bytes.find("<VTKFile"), "header_type") == "UInt64";
  const std::size_t n = std::stoull(attribute(bytes, piece, "NumberOfPoints"));
  const std::size_t base = bytes.find('_', appended) + 1;
  const std::size_t points = bytes.find("<Points>");
  if (points == std::string::npos || points > appended) throw InputError(path + ": the .vtu file has no <Points>");
  PointFile out;
  out.positions = vtuVectors(bytes, bytes.find("<DataArray", points), base, n, header64, path);
  for (std::size_t tag = bytes.find("<DataArray", piece); tag != std::string::npos && tag < appended; tag = bytes.find("<DataArray", tag + 1))
    if (attribute(bytes, tag, "Name") == "velocity") out.velocities = vtuVectors(bytes, tag, base, n, header64, path);
  return out;
}

// ---- BGEO: Houdini's classic binary geometry, big-endian, as partio writes and reads it ----
// 'B' 'g' 'e' 'o' 'V', int32 version, then int32 counts: points, primitives, point groups,
// primitive groups, point attributes, vertex attributes, primitive attributes, detail attributes.
// Each point attribute: int16 name length, name, int16 size (components), int32 type (0 float,
// 1 int, 4 index/string, 5 vector) and its defaults. Then per point x, y, z, w (float32) and the
// attributes' values in their order, 4 bytes per component.

PointFile readBgeo(const std::string& compressed, const std::string& path) {
  const std::string bytes = gunzip(compressed, path);
  if (bytes.size() < 5 || bytes.compare(0, 5, "BgeoV") != 0) throw InputError(path + ": not a Houdini .bgeo file (no 'BgeoV' magic)");
  ByteReader in(bytes, 5, true, path);
  const std::int32_t version = in.read<std::int32_t>();
  if (version != 5) throw InputError(path + ": .bgeo version " + std::to_string(version) + " is not read (only version 5, as partio writes)");
  std::int32_t counts[8];
  for (auto& c : counts) c = in.read<std::int32_t>();
  const std::int32_t nPoints = counts[0], nPointAttributes = counts[4];
  if (nPoints < 0 || nPointAttributes < 0) throw InputError(path + ": negative counts in the .bgeo header");
  struct Attribute {
    std::string name;
    int size, type;
  };
  std::vector<Attribute> attributes;
  for (int a = 0; a < nPointAttributes; ++a) {
    Attribute attr;
    attr.name = in.text(std::size_t(std::max<std::int16_t>(in.read<std::int16_t>(), 0)));
    attr.size = in.read<std::int16_t>();
    attr.type = in.read<std::int32_t>();
    if (attr.size < 0) throw InputError(path + ": attribute '" + attr.name + "' has a negative size");
    if (attr.type == 4) {  // an index attribute: its strings instead of defaults
      const std::int32_t strings = in.read<std::int32_t>();
      for (std::int32_t s = 0; s < strings; ++s) in.skip(std::size_t(std::max<std::int16_t>(in.read<std::int16_t>(), 0)));
    } else if (attr.type == 0 || attr.type == 1 || attr.type == 5) {
      in.skip(4 * std::size_t(attr.size));
    } else {
      throw InputError(path + ": attribute '" + attr.name + "' has Houdini type " + std::to_string(attr.type) + ", which is not read");
    }
    attributes.push_back(attr);
  }
  PointFile out;
  out.positions.resize(std::size_t(nPoints));
  int velocity = -1;
  for (std::size_t a = 0; a < attributes.size(); ++a)
    if (attributes[a].name == "v" && attributes[a].size == 3 && (attributes[a].type == 0 || attributes[a].type == 5)) velocity = int(a);
  if (velocity >= 0) out.velocities.resize(std::size_t(nPoints));
  for (std::int32_t i = 0; i < nPoints; ++i) {
    const float x = in.read<float>(), y = in.read<float>(), z = in.read<float>();
    in.skip(4);  // w
    out.positions[std::size_t(i)] = Vector3r(Real(x), Real(y), Real(z));
    for (std::size_t a = 0; a < attributes.size(); ++a) {
      if (int(a) == velocity) {
        const float vx = in.read<float>(), vy = in.read<float>(), vz = in.read<float>();
        out.velocities[std::size_t(i)] = Vector3r(Real(vx), Real(vy), Real(vz));
      } else {
        in.skip(4 * std::size_t(attributes[a].size));
      }
    }
  }
  return out;
}

}  // namespace

PointFile readPointFile(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  if (extension != ".ply" && extension != ".vtu" && extension != ".bgeo")
    throw InputError(path + ": point files are .ply, .vtu or .bgeo");
  const std::string bytes = readWholeFile(path);
  PointFile points = extension == ".ply" ? readPly(bytes, path) : extension == ".vtu" ? readVtu(bytes, path) : readBgeo(bytes, path);
  for (const Vector3r& x : points.positions)
    if (!x.allFinite()) throw InputError(path + ": a position is not a finite number");
  for (const Vector3r& v : points.velocities)
    if (!v.allFinite()) throw InputError(path + ": a velocity is not a finite number");
  return points;
}

}  // namespace consph
