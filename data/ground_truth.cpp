#include "data/ground_truth.h"

namespace dslam {

bool GroundTruth::pointWorld(int64_t track_id, int frame, Vec3* p_world) const {
  if (auto it = static_points_world.find(track_id); it != static_points_world.end()) {
    *p_world = it->second;
    return true;
  }
  const auto it = object_points.find(track_id);
  if (it == object_points.end()) return false;
  const auto obj = objects.find(it->second.object_id);
  if (obj == objects.end()) return false;
  const auto pose = obj->second.L_world_object.find(frame);
  if (pose == obj->second.L_world_object.end()) return false;
  *p_world = pose->second * it->second.p_body;
  return true;
}

}  // namespace dslam
