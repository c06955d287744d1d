#include "data/ground_truth.h"

#include <algorithm>
#include <iterator>

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

void TruncateGroundTruth(int frames, GroundTruth* gt) {
  if (frames < static_cast<int>(gt->T_world_camera.size())) gt->T_world_camera.resize(std::max(0, frames));
  const auto cut = [frames](auto& by_frame) { by_frame.erase(by_frame.lower_bound(frames), by_frame.end()); };
  for (auto it = gt->objects.begin(); it != gt->objects.end();) {
    ObjectGroundTruth& o = it->second;
    cut(o.L_world_object);
    cut(o.centroid_world);
    cut(o.observed_frames);
    if (o.measurable_frames) cut(*o.measurable_frames);
    it = o.L_world_object.empty() ? gt->objects.erase(it) : std::next(it);
  }
}

}  // namespace dslam
