// What a frame writer (VTU, BGEO, PLY) reads: n points with their positions and named per-point
// columns (a scalar, a 3-vector or a 4-vector of Real, or an unsigned integer), and optionally
// triangles over the points (a surface mesh). The table only points at the data; it owns none.
#pragma once
#include <array>
#include <string>
#include <vector>

#include "Utilities/Types.h"

namespace consph {

// The floating-point type of a frame's values: frames are float32 unless asked for double
// (half the size, and what Houdini, Blender and ParaView show anyway).
enum class FramePrecision { Float, Double };

struct PointColumn {
  std::string name;
  int components = 1;    // 1, 3 or 4
  bool integer = false;  // Index values (uint32); else Real
  const void* data = nullptr;  // (n x components) values
};

struct PointTable {
  const Vector3r* positions = nullptr;
  std::size_t size = 0;
  std::vector<PointColumn> columns;
  const std::array<Index, 3>* triangles = nullptr;  // null: a point cloud
  std::size_t triangleCount = 0;

  void addReal(const std::string& name, const Real* values, int components) {
    columns.push_back({name, components, false, values});
  }
  void addIndex(const std::string& name, const Index* values) { columns.push_back({name, 1, true, values}); }
  // Component c of point i of column `col` as a double / an unsigned integer.
  double real(const PointColumn& col, std::size_t i, int c) const {
    return double(static_cast<const Real*>(col.data)[i * std::size_t(col.components) + std::size_t(c)]);
  }
  Index index(const PointColumn& col, std::size_t i) const { return static_cast<const Index*>(col.data)[i]; }
};

}  // namespace consph
