#pragma once
// What an estimator hands its result sinks: camera poses, object motions with velocities, and the
// estimated world position of every point observation (for the structure error).

#include <cstdint>
#include <vector>

#include "geometry/se3.h"

namespace dslam {

struct ObjectMotionEstimate {
  int object_id = 0;
  int frame = 0;  // motion over frame-1 -> frame
  bool is_dynamic = true;
  SE3 H_world;                      // identity when static
  Vec3 centroid_prev_world = Vec3::Zero();
  Vec3 velocity_world_per_frame = Vec3::Zero();  // metres per frame
  double speed_mps = 0.0;
};

struct PointEstimate {
  int frame = 0;
  int64_t track_id = 0;
  int object_id = -1;
  Vec3 p_world = Vec3::Zero();
};

struct Estimate {
  std::vector<SE3> T_world_camera;
  std::vector<ObjectMotionEstimate> object_motions;  // only transitions that received an estimate
  std::vector<PointEstimate> points;
};

}  // namespace dslam
