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

// Whether `file` is a map this version can never load: volumemap_KEY.state (format 1-3 named
// no version) or volumemap_vN_KEY.state with another N. Other files are never touched.
bool olderFormatFile(const std::string& file) {
  const std::string prefix = "volumemap_", suffix = ".state";
  if (file.size() <= prefix.size() + suffix.size() || file.rfind(prefix, 0) != 0 ||
      file.compare(file.size() - suffix.size(), suffix.size(), suffix) != 0)
    return false;
  const std::string middle = file.substr(prefix.size(), file.size() - prefix.size() - suffix.size());
  const auto hex = [](const std::string& t) {
    return t.size() == 16 && t.find_first_not_of("0123456789abcdef") == std::string::npos;
  };
  if (hex(middle)) return true;
  const std::size_t underscore = middle.find('_');
  if (middle[0] != 'v' || underscore == std::string::npos || !hex(middle.substr(underscore + 1))) return false;
  const std::string version = middle.substr(1, underscore - 1);
  return !version.empty() && version.find_first_not_of("0123456789") == std::string::npos &&
         version != std::to_string(kFormatVersion);
}
}  // namespace

VolumeMapCache::VolumeMapCache(std::string directory, LogSink log) : directory_(std::move(directory)), log_(std::move(log)) {}

std::string VolumeMapCache::pathOf(const BoundaryObject& object, const CubicSplineKernel& kernel, Real cellSize, Real surfaceOffset) const {
  if (directory_.empty()) return "";
  char name[64];
  std::snprintf(name, sizeof(name), "volumemap_v%d_%016llx.state", kFormatVersion,
                (unsigned long long)fnv1a(mapInputs(object, kernel, cellSize, surfaceOffset)));
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
  // Maps of an older format would only ever miss: they go when a new one is stored.
  std::size_t removed = 0;
  for (const auto& entry : std::filesystem::directory_iterator(directory_, ec))
    if (olderFormatFile(entry.path().filename().string()) && std::filesystem::remove(entry.path(), ec)) ++removed;
  if (removed > 0) say(LogLevel::Info, "volume map cache: removed " + std::to_string(removed) + " map(s) of an older format from " + directory_);
  return map;
}

}  // namespace consph
