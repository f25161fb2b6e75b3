#include "Boundary/VolumeMapCache.h"

#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "Utilities/Timer.h"

namespace consph {

namespace {
// Bump when VolumeMap's construction or its saved blocks change: old files then miss.
constexpr int kFormatVersion = 3;  // 2: the object's mapThickness; 3: stored in bricks

// The inputs a map depends on, as bytes: hashed for the file name, stored in the file and
// compared on load.
std::string mapInputs(const BoundaryObject& o, const CubicSplineKernel& kernel, Real cellSize, Real surfaceOffset) {
  StateWriter w;
  w.put("version", kFormatVersion);
  w.put("realBytes", int(sizeof(Real)));
  w.put("h", kernel.supportRadius());
  w.put("cellSize", cellSize);
  w.put("surfaceOffset", surfaceOffset);
  w.put("thickness", o.mapThickness);
  w.put("isBox", o.isBox);
  w.put("inverted", o.inverted);
  w.put("box", std::array<Real, 6>{o.boxMin[0], o.boxMin[1], o.boxMin[2], o.boxMax[0], o.boxMax[1], o.boxMax[2]});
  std::vector<Real> vertices;
  vertices.reserve(3 * o.mesh.vertices.size());
  for (const Vector3r& v : o.mesh.vertices) vertices.insert(vertices.end(), {v[0], v[1], v[2]});
  w.putVector("vertices", vertices);
  w.putVector("triangles", o.mesh.triangles);
  return w.bytes();
}

std::uint64_t fnv1a(const std::string& bytes) {
  std::uint64_t h = 14695981039346656037ull;
  for (unsigned char c : bytes) h = (h ^ c) * 1099511628211ull;
  return h;
}

std::string label(const BoundaryObject& o) { return o.name.empty() ? o.path : "'" + o.name + "' (" + o.path + ")"; }
}  // namespace

VolumeMapCache::VolumeMapCache(std::string directory, LogSink log) : directory_(std::move(directory)), log_(std::move(log)) {}

std::string VolumeMapCache::pathOf(const BoundaryObject& object, const CubicSplineKernel& kernel, Real cellSize, Real surfaceOffset) const {
  if (directory_.empty()) return "";
  char name[64];
  std::snprintf(name, sizeof(name), "volumemap_%016llx.state", (unsigned long long)fnv1a(mapInputs(object, kernel, cellSize, surfaceOffset)));
  return (std::filesystem::path(directory_) / name).string();
}

std::unique_ptr<VolumeMap> VolumeMapCache::obtain(const BoundaryObject& object, const CubicSplineKernel& kernel, Real cellSize,
                                                  Real surfaceOffset) {
  auto say = [&](LogLevel level, const std::string& text) {
    if (log_) log_(level, text);
  };
  const std::string path = pathOf(object, kernel, cellSize, surfaceOffset);
  const std::string inputs = path.empty() ? std::string() : mapInputs(object, kernel, cellSize, surfaceOffset);
  Timer timer;
  if (!path.empty() && std::filesystem::exists(path)) {
    try {
      std::ifstream file(path, std::ios::binary);
      std::stringstream buffer;
      buffer << file.rdbuf();
      const StateReader in(buffer.str(), path);
      if (in.bytes("inputs") == inputs) {
        std::unique_ptr<VolumeMap> map = VolumeMap::load(in);
        ++loads_;
        char text[96];
        std::snprintf(text, sizeof(text), " (%zu nodes, %.3f s)", map->nodeCount(), timer.seconds());
        say(LogLevel::Info, "volume map of " + label(object) + ": loaded from " + path + text);
        return map;
      }
    } catch (const std::exception& e) {
      say(LogLevel::Warning, "volume map cache: " + std::string(e.what()) + "; building the map again");
    }
  }
  auto map = std::make_unique<VolumeMap>(object, kernel, cellSize, surfaceOffset);
  ++builds_;
  const double buildSeconds = timer.seconds();
  if (path.empty()) return map;
  // A unique temporary per process and call: runs sharing the cache never write the same file.
  static std::atomic<unsigned> counter{0};
  const std::string tmp = path + "." + std::to_string(::getpid()) + "." + std::to_string(counter++) + ".tmp";
  std::error_code ec;
  std::filesystem::create_directories(directory_, ec);
  StateWriter out;
  out.putString("inputs", inputs);
  map->save(out);
  {
    std::ofstream file(tmp, std::ios::binary | std::ios::trunc);
    file.write(out.bytes().data(), std::streamsize(out.bytes().size()));
    file.close();
    if (!file) ec = std::make_error_code(std::errc::io_error);
  }
  if (!ec) std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    say(LogLevel::Warning, "volume map cache: cannot store " + path + " (the map is used, not cached)");
    return map;
  }
  char text[96];
  std::snprintf(text, sizeof(text), " (%zu nodes, %.3f s)", map->nodeCount(), buildSeconds);
  say(LogLevel::Info, "volume map of " + label(object) + ": built and stored in " + path + text);
  return map;
}

}  // namespace consph
