// Interface of boundary models (particle boundaries after Akinci 2012, volume maps, ...).
// A model turns the scene's boundary objects into BoundarySamples and finds, every step, the
// samples near each fluid particle. Solvers and forces see only those samples.
#pragma once
#include <string>
#include <vector>

#include "Simulation/BoundarySamples.h"
#include "Simulation/FluidModel.h"
#include "Simulation/NeighborSearch.h"
#include "Utilities/TriangleMesh.h"

namespace consph {

// One boundary object of the scene, its geometry already in world space.
struct BoundaryObject {
  std::string name;
  TriangleMesh mesh;
  bool isBox = false;  // an axis-aligned box [boxMin, boxMax]: sampled on regular face grids
  Vector3r boxMin = Vector3r::Zero(), boxMax = Vector3r::Zero();
  bool inverted = false;  // the fluid is inside (a container)
};

class BoundaryModel {
 public:
  virtual ~BoundaryModel() = default;
  virtual void initialize(const std::vector<BoundaryObject>& objects, Real density0, const CubicSplineKernel& kernel) = 0;
  // Fills fluid i -> boundary sample k lists (with cached kernel gradients).
  virtual void findNeighbors(const FluidModel& fluid, const CubicSplineKernel& kernel, NeighborLists& out) = 0;
  // Samples moved (a moving body): the model must rebuild its acceleration structure.
  void markMoved() { moved_ = true; }
  BoundarySamples& samples() { return samples_; }
  const BoundarySamples& samples() const { return samples_; }

 protected:
  BoundarySamples samples_;
  bool moved_ = true;
};

}  // namespace consph
