#include "Simulation/FrameSeries.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "Simulation/MovingBodies.h"
#include "Utilities/BgeoWriter.h"
#include "Utilities/Error.h"
#include "Utilities/Gzip.h"
#include "Utilities/PlyWriter.h"
#include "Utilities/VtkWriter.h"

namespace consph {

std::string serializeFrame(const PointTable& table, FrameFormat format, FramePrecision precision, bool compressed) {
  switch (format) {
    case FrameFormat::Vtu: return serializeVtu(table, precision);
    case FrameFormat::Ply: return serializePly(table, precision);
    case FrameFormat::Bgeo: {
      std::string bytes = serializeBgeo(table);
      // Level 1: particle frames compress ~2x at any level; higher levels only cost time.
      return compressed ? gzipCompress(bytes, 1) : bytes;
    }
  }
  return {};
}

namespace {
// Houdini's attribute names where they differ from consph's field names.
std::string exportedName(const std::string& field, FrameFormat format) {
  if (format != FrameFormat::Bgeo) return field;
  if (field == "velocity") return "v";
  if (field == "angularVelocity") return "w";
  return field;
}

std::string fieldNames(const ParticleFields& fields) {
  std::vector<std::string> names;
  for (auto& f : fields.all()) names.push_back(f->name());
  std::sort(names.begin(), names.end());
  std::string list;
  for (auto& n : names) list += (list.empty() ? "" : ", ") + n;
  return list;
}
}  // namespace

void checkAttributes(const ParticleFields& fields, const std::vector<std::string>& attributes, const std::string& path) {
  for (std::size_t i = 0; i < attributes.size(); ++i)
    if (!fields.has(attributes[i]))
      throw InputError(path + "[" + std::to_string(i) + "]: unknown particle field '" + attributes[i] + "'; valid are: " + fieldNames(fields));
}

PointTable particleTable(ParticleFields& fields, std::size_t n, const std::vector<std::string>& attributes, FrameFormat format) {
  FieldBase* positions = fields.find("position");
  PointTable table;
  table.positions = static_cast<const Vector3r*>(positions->data());
  table.size = n;
  auto add = [&](FieldBase& f) {
    if (&f == positions) return;
    const std::string name = exportedName(f.name(), format);
    if (f.type() == FieldType::Index) table.addIndex(name, static_cast<const Index*>(f.data()));
    else table.addReal(name, static_cast<const Real*>(f.data()), f.components());
  };
  if (attributes.empty()) {
    for (auto& f : fields.all())
      if (f->flags() & FieldExported) add(*f);
  } else {
    for (const std::string& name : attributes) add(*fields.find(name));
  }
  return table;
}

BodyFrame::BodyFrame(const MovingBodies& system, BodyFrames kind, FrameFormat format) {
  if (kind == BodyFrames::Meshes) {
    system.worldMeshes(mesh_, body_, velocity_);
    table_.positions = mesh_.vertices.data();
    table_.size = mesh_.vertices.size();
    table_.triangles = mesh_.triangles.data();
    table_.triangleCount = mesh_.triangles.size();
    table_.addIndex("body", body_.data());
    table_.addReal(exportedName("velocity", format), reinterpret_cast<const Real*>(velocity_.data()), 3);
    return;
  }
  for (std::size_t i = 0; i < system.count(); ++i) {
    const MovingBodyState b = system.state(i);
    points_.push_back(b.x);
    pivot_.push_back(b.x0);
    velocity_.push_back(b.v);
    angular_.push_back(b.w);
    body_.push_back(b.object);
    for (Real c : {b.q.x(), b.q.y(), b.q.z(), b.q.w()}) orient_.push_back(c);
  }
  table_.positions = points_.data();
  table_.size = points_.size();
  table_.addReal("orient", orient_.data(), 4);
  table_.addReal("pivot", reinterpret_cast<const Real*>(pivot_.data()), 3);
  table_.addReal(exportedName("velocity", format), reinterpret_cast<const Real*>(velocity_.data()), 3);
  table_.addReal(exportedName("angularVelocity", format), reinterpret_cast<const Real*>(angular_.data()), 3);
  table_.addIndex("body", body_.data());
}

FrameSeries::FrameSeries(std::string directory, std::string name, FrameFormat format, FramePrecision precision)
    : directory_(std::move(directory)), name_(std::move(name)), format_(format), precision_(precision) {
  if (format_ == FrameFormat::Vtu) vtk_ = std::make_unique<VtkSeries>(directory_, name_);
  std::error_code ec;
  std::filesystem::create_directories(directory_, ec);
  if (ec) throw OutputError("cannot create output folder '" + directory_ + "': " + ec.message());
}

FrameSeries::~FrameSeries() = default;

std::string FrameSeries::write(std::size_t index, double time, const PointTable& table) {
  if (vtk_) {
    const std::string path = vtk_->write(index, time, serializeVtu(table, precision_));
    frames_ = vtk_->frames();
    return path;
  }
  char file[256];
  std::snprintf(file, sizeof(file), "%s_%05zu%s", name_.c_str(), index, frameExtension(format_));
  const std::string path = (std::filesystem::path(directory_) / file).string();
  writeFileAtomically(path, serializeFrame(table, format_, precision_));
  frames_.emplace_back(time, file);
  return path;
}

void FrameSeries::setFrames(std::vector<std::pair<double, std::string>> frames) {
  frames_ = std::move(frames);
  if (vtk_) vtk_->setFrames(frames_);
}

}  // namespace consph
