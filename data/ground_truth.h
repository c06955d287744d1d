#pragma once
// Ground truth that comes with a sequence, used only by the evaluation.

#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "geometry/se3.h"

namespace dslam {

struct ObjectGroundTruth {
  int object_id = 0;
  std::string category = "VEHICLE";
  std::map<int, SE3> L_world_object;   // object pose per frame (body frame: dataset-defined)
  std::map<int, Vec3> centroid_world;  // reference point whose displacement defines the true speed
  std::set<int> observed_frames;       // frames in which the sensor sees it (after range gating)
  // Frames k whose pair k-1 -> k can be measured: at least kMinMeasurablePoints of the same surface points
  // seen in both frames. Known where the source knows its points (the simulator, the replay); absent
  // elsewhere.
  std::optional<std::set<int>> measurable_frames;
  std::optional<Vec3> box_lwh;         // box size (length, width, height) when the object is a box
};

// Points of one surface seen in both frames of a pair for the pair to count as measurable.
constexpr int kMinMeasurablePoints = 3;

struct GroundTruth {
  std::vector<SE3> T_world_camera;  // one per frame
  std::map<int, ObjectGroundTruth> objects;
  std::unordered_map<int64_t, Vec3> static_points_world;  // track id -> world position
  struct BodyPoint {
    int object_id;
    Vec3 p_body;
  };
  std::unordered_map<int64_t, BodyPoint> object_points;  // track id -> point fixed in the body frame
  // When the run's masks are not the dataset's (made from the LiDAR, say), its object ids are its own:
  // (frame, ground-truth object id) -> the run's id of that object in that frame, found by where the run's
  // object points fall in the dataset's own masks. Absent: the run's ids are the ground truth's.
  std::optional<std::map<std::pair<int, int>, int>> run_object_ids;

  // World position of a tracked point at frame k; false when the track id is unknown.
  bool pointWorld(int64_t track_id, int frame, Vec3* p_world) const;
};

// Keeps the first `frames` frames (a run that stopped early): camera poses and each object's per-frame
// entries beyond them go, and objects with none left.
void TruncateGroundTruth(int frames, GroundTruth* gt);

}  // namespace dslam
