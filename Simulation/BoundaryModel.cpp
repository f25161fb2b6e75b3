#include "Simulation/BoundaryModel.h"

#include "Utilities/ParallelFor.h"

namespace consph {

void BoundaryModel::follow(const std::vector<PoseUpdate>& poses) {
  for (const PoseUpdate& u : poses) {
    if (u.object >= objectSamples_.size()) objectSamples_.resize(u.object + 1);
    ObjectSamples& own = objectSamples_[u.object];
    if (!own.known) {
      // First pose (start-up): the samples are where the scene put them.
      for (std::size_t k = 0; k < samples_.size(); ++k)
        if (samples_.bodies[k] == u.object) {
          own.samples.push_back(Index(k));
          own.initialPositions.push_back(samples_.positions[k]);
        }
      own.known = true;
    }
    const ObjectPose& pose = u.pose;
    parallelFor(own.samples.size(), [&](std::size_t s) {
      const Index k = own.samples[s];
      samples_.positions[k] = pose.centre + pose.rotation * (own.initialPositions[s] - pose.initialCentre);
      samples_.velocities[k] = pose.velocityAt(samples_.positions[k]);
    });
    onPose(u.object, pose);
    if (u.moved) moved_ = true;
  }
}

}  // namespace consph
