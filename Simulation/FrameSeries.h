// A run's frames in the format its scene asks for (output.format): NAME_00000.vtu ... with
// NAME.pvd for ParaView, NAME_00000.bgeo.gz ... for Houdini ($F5 sequences), NAME_00000.ply ...
// for Blender. Every file is written to a temporary name and renamed (writeFileAtomically), and
// each name is one OutputFolder counts as the run's.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "Simulation/FrameFormat.h"
#include "Simulation/ParticleFields.h"
#include "Utilities/PointTable.h"
#include "Utilities/TriangleMesh.h"

namespace consph {

class VtkSeries;
class MovingBodies;

// The bytes of one frame file: VTU, BGEO (gzip-compressed when `compressed`; always float32,
// the format has no double) or PLY.
std::string serializeFrame(const PointTable& table, FrameFormat format, FramePrecision precision, bool compressed = true);

// The particle fields a frame holds: `attributes` by name (empty: every FieldExported field),
// positions always (as the points). BGEO names velocity "v", Houdini's name for it.
PointTable particleTable(ParticleFields& fields, std::size_t n, const std::vector<std::string>& attributes, FrameFormat format);

// Refuses (InputError naming `path`[i]) an attribute that is no field of `fields`, listing those there are.
void checkAttributes(const ParticleFields& fields, const std::vector<std::string>& attributes, const std::string& path);

// The moving bodies of one frame as a point table and the data it points at.
class BodyFrame {
 public:
  // Meshes: every body's surface where it is now, with per-vertex "body" (its object index) and
  // "velocity". Transforms: one point per body at its centre of mass with "orient" (the
  // quaternion body -> world, x y z w as Houdini orders it), "pivot" (the centre at t = 0, so
  // that a vertex p of the scene's mesh is at P + orient (p - pivot)), "velocity" ("v" in BGEO),
  // "angularVelocity" ("w") and "body".
  BodyFrame(const MovingBodies& bodies, BodyFrames kind, FrameFormat format);
  const PointTable& table() const { return table_; }

 private:
  TriangleMesh mesh_;
  std::vector<Vector3r> points_, velocity_, angular_, pivot_;
  std::vector<Real> orient_;
  std::vector<Index> body_;
  PointTable table_;
};

class FrameSeries {
 public:
  FrameSeries(std::string directory, std::string name, FrameFormat format, FramePrecision precision);
  ~FrameSeries();
  // Writes frame `index` at simulated time `time`; returns its path.
  std::string write(std::size_t index, double time, const PointTable& table);
  // The frames written so far (time, file name): a restarted run lists the earlier ones again.
  const std::vector<std::pair<double, std::string>>& frames() const { return frames_; }
  void setFrames(std::vector<std::pair<double, std::string>> frames);

 private:
  std::string directory_, name_;
  FrameFormat format_;
  FramePrecision precision_;
  std::unique_ptr<VtkSeries> vtk_;  // VTU only: it keeps NAME.pvd
  std::vector<std::pair<double, std::string>> frames_;
};

}  // namespace consph
