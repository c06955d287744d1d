#pragma once
// Ground-truth replay (docs/design.md §10): the real KITTI camera path and object boxes with synthetic
// measurements — static points on facades and the road along the path, object points on the visible
// faces of the real boxes (fixed in the body frame), Gaussian point noise, odometry noise, objects
// gated by distance. Seeded and deterministic; nothing depends on the sequence number.

#include <cstdint>

#include "data/kitti_dataset.h"
#include "data/sequence.h"
#include "simulation/sensor_simulator.h"

namespace dslam {

struct KittiReplayOptions {
  uint64_t seed = 1;
  SimNoise noise;
  double object_max_range_m = 22.0;  // as the paper's KITTI runs
  double camera_height_m = 1.65;     // KITTI's camera above the road, for the road points
};

// The replay's frames one at a time (what `dslam kitti-replay` runs), or all at once.
SensorSimulator MakeKittiReplaySimulator(const KittiGroundTruthSequence& gt, const KittiReplayOptions& options);
Sequence MakeKittiReplay(const KittiGroundTruthSequence& gt, const KittiReplayOptions& options);

}  // namespace dslam
