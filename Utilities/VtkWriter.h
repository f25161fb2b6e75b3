// Binary VTK XML output (.vtu, appended raw data) that ParaView opens, plus a .pvd collection.
// Every file is written to a temporary name and renamed, so a crash never leaves half a frame.
#pragma once
#include <array>
#include <string>
#include <vector>

#include "Utilities/PointTable.h"

namespace consph {

// Writes `contents` to `path` atomically (temporary file in the same folder, then rename; the
// temporary is removed on failure). A path that is not a regular file (/dev/stdout, a FIFO) is
// written in place. Failures throw OutputError.
void writeFileAtomically(const std::string& path, const std::string& contents);

// One point cloud: positions and named point arrays; with triangles, a surface mesh instead.
class VtuPointCloud {
 public:
  VtuPointCloud(const Vector3r* positions, std::size_t n) : positions_(positions), n_(n) {}
  void add(const std::string& name, const Real* values, int components);
  void add(const std::string& name, const Index* values);
  // Cells become these triangles (indices into the points) instead of one vertex per point.
  void setTriangles(const std::array<Index, 3>* triangles, std::size_t count) {
    triangles_ = triangles;
    nTriangles_ = count;
  }
  // Float: Real arrays (and the points) are written as Float32 even in a double build.
  void setPrecision(FramePrecision precision) { precision_ = precision; }
  std::string serialize() const;

 private:
  struct Array {
    std::string name, type;
    int components;
    const void* data;
    std::size_t bytes;
  };
  const Vector3r* positions_;
  std::size_t n_;
  const std::array<Index, 3>* triangles_ = nullptr;
  std::size_t nTriangles_ = 0;
  std::vector<Array> arrays_;
  FramePrecision precision_ = sizeof(Real) == 8 ? FramePrecision::Double : FramePrecision::Float;
};

// The .vtu of a point table (a mesh when it has triangles).
std::string serializeVtu(const PointTable& table, FramePrecision precision);

// A time series: NAME_00000.vtu, ... and NAME.pvd listing them with their times.
class VtkSeries {
 public:
  VtkSeries(std::string directory, std::string name);
  // Writes frame `index` at simulated time `time`; returns its path.
  std::string write(std::size_t index, double time, const std::string& vtuContents);
  // The frames listed in NAME.pvd (time, file name); a restarted run sets the earlier ones.
  const std::vector<std::pair<double, std::string>>& frames() const { return frames_; }
  void setFrames(std::vector<std::pair<double, std::string>> frames) { frames_ = std::move(frames); }

 private:
  std::string directory_, name_;
  std::vector<std::pair<double, std::string>> frames_;
};

}  // namespace consph
