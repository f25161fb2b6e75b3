#include "Utilities/VtkWriter.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "Utilities/Error.h"

namespace consph {

namespace {
// Writes `contents` to `path` (truncating); false when opening, writing or closing failed.
bool writeInPlace(const std::string& path, const std::string& contents) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) return false;
  out.write(contents.data(), std::streamsize(contents.size()));
  out.close();  // a full disk often shows only when the buffer is flushed
  return bool(out);
}
}  // namespace

void writeFileAtomically(const std::string& path, const std::string& contents) {
  namespace fs = std::filesystem;
  std::error_code ec;
  // A device, FIFO or socket (/dev/stdout, a named pipe) is written in place: renaming over it
  // would replace it with a regular file. A symlink to a regular file: the file it names is
  // replaced, the link stays.
  const fs::file_status status = fs::status(path, ec);
  if (fs::exists(status) && !fs::is_regular_file(status) && !fs::is_directory(status)) {
    if (!writeInPlace(path, contents)) throw OutputError("cannot write '" + path + "'");
    return;
  }
  const std::string target = fs::is_symlink(fs::symlink_status(path, ec)) ? fs::canonical(path, ec).string() : path;
  const std::string tmp = (target.empty() ? path : target) + ".tmp";
  if (!writeInPlace(tmp, contents)) {
    fs::remove(tmp, ec);  // no partial file left behind
    throw OutputError("cannot write '" + tmp + "' (disk full, or no permission?)");
  }
  fs::rename(tmp, target.empty() ? path : target, ec);
  if (ec) {
    const std::string why = ec.message();
    fs::remove(tmp, ec);
    throw OutputError("cannot rename '" + tmp + "' to '" + path + "': " + why);
  }
}

namespace {
constexpr const char* realType() { return sizeof(Real) == 8 ? "Float64" : "Float32"; }
}  // namespace

void VtuPointCloud::add(const std::string& name, const Real* values, int components) {
  arrays_.push_back({name, realType(), components, values, n_ * components * sizeof(Real)});
}
void VtuPointCloud::add(const std::string& name, const Index* values) {
  arrays_.push_back({name, "UInt32", 1, values, n_ * sizeof(Index)});
}

std::string VtuPointCloud::serialize() const {
  const bool mesh = triangles_ != nullptr;
  const std::size_t cells = mesh ? nTriangles_ : n_;
  std::vector<std::int64_t> connectivity, offsets(cells);
  std::vector<std::uint8_t> types(cells, mesh ? 5 : 1);  // VTK_TRIANGLE or VTK_VERTEX
  connectivity.reserve(mesh ? 3 * cells : cells);
  for (std::size_t c = 0; c < cells; ++c) {
    if (mesh)
      for (Index v : triangles_[c]) connectivity.push_back(std::int64_t(v));
    else
      connectivity.push_back(std::int64_t(c));
    offsets[c] = std::int64_t(connectivity.size());
  }
  std::ostringstream xml, data;
  std::uint64_t offset = 0;
  auto appended = [&](const void* p, std::size_t bytes) {
    const std::uint64_t header = bytes;
    data.write(reinterpret_cast<const char*>(&header), sizeof(header));
    data.write(static_cast<const char*>(p), std::streamsize(bytes));
    const std::uint64_t at = offset;
    offset += sizeof(header) + bytes;
    return at;
  };
  // A double build's Real arrays narrowed to float32 when a Float frame is asked for.
  const bool narrow = sizeof(Real) == 8 && precision_ == FramePrecision::Float;
  const char* floatType = narrow ? "Float32" : realType();
  std::vector<float> narrowed;
  auto appendedReal = [&](const void* p, std::size_t bytes) {
    if (!narrow) return appended(p, bytes);
    const Real* values = static_cast<const Real*>(p);
    narrowed.assign(values, values + bytes / sizeof(Real));
    return appended(narrowed.data(), narrowed.size() * sizeof(float));
  };
  xml << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
         "header_type=\"UInt64\">\n<UnstructuredGrid>\n<Piece NumberOfPoints=\""
      << n_ << "\" NumberOfCells=\"" << cells << "\">\n<PointData>\n";
  for (auto& a : arrays_) {
    const bool real = a.type == realType();
    xml << "<DataArray type=\"" << (real ? floatType : a.type.c_str()) << "\" Name=\"" << a.name << "\" NumberOfComponents=\""
        << a.components << "\" format=\"appended\" offset=\""
        << (real ? appendedReal(a.data, a.bytes) : appended(a.data, a.bytes)) << "\"/>\n";
  }
  xml << "</PointData>\n<Points>\n<DataArray type=\"" << floatType
      << "\" NumberOfComponents=\"3\" format=\"appended\" offset=\"" << appendedReal(positions_, n_ * 3 * sizeof(Real))
      << "\"/>\n</Points>\n<Cells>\n";
  xml << "<DataArray type=\"Int64\" Name=\"connectivity\" format=\"appended\" offset=\""
      << appended(connectivity.data(), connectivity.size() * 8) << "\"/>\n";
  xml << "<DataArray type=\"Int64\" Name=\"offsets\" format=\"appended\" offset=\"" << appended(offsets.data(), cells * 8)
      << "\"/>\n";
  xml << "<DataArray type=\"UInt8\" Name=\"types\" format=\"appended\" offset=\"" << appended(types.data(), cells)
      << "\"/>\n";
  xml << "</Cells>\n</Piece>\n</UnstructuredGrid>\n<AppendedData encoding=\"raw\">\n_";
  std::string out = xml.str();
  out += data.str();
  out += "\n</AppendedData>\n</VTKFile>\n";
  return out;
}

std::string serializeVtu(const PointTable& table, FramePrecision precision) {
  VtuPointCloud cloud(table.positions, table.size);
  if (table.triangles) cloud.setTriangles(table.triangles, table.triangleCount);
  for (const PointColumn& c : table.columns) {
    if (c.integer) cloud.add(c.name, static_cast<const Index*>(c.data));
    else cloud.add(c.name, static_cast<const Real*>(c.data), c.components);
  }
  cloud.setPrecision(precision);
  return cloud.serialize();
}

VtkSeries::VtkSeries(std::string directory, std::string name) : directory_(std::move(directory)), name_(std::move(name)) {
  std::error_code ec;
  std::filesystem::create_directories(directory_, ec);
  if (ec) throw OutputError("cannot create output folder '" + directory_ + "': " + ec.message());
}

std::string VtkSeries::write(std::size_t index, double time, const std::string& vtuContents) {
  char file[256];
  std::snprintf(file, sizeof(file), "%s_%05zu.vtu", name_.c_str(), index);
  const std::string path = (std::filesystem::path(directory_) / file).string();
  writeFileAtomically(path, vtuContents);
  frames_.emplace_back(time, file);
  std::ostringstream pvd;
  pvd << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n<Collection>\n";
  for (auto& [t, f] : frames_) pvd << "<DataSet timestep=\"" << t << "\" group=\"\" part=\"0\" file=\"" << f << "\"/>\n";
  pvd << "</Collection>\n</VTKFile>\n";
  writeFileAtomically((std::filesystem::path(directory_) / (name_ + ".pvd")).string(), pvd.str());
  return path;
}

}  // namespace consph
