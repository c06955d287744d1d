#pragma once
// Ground truth of one KITTI tracking sequence, from either layout:
//  - KITTI's own: DIR/label_02/SSSS.txt, DIR/calib/SSSS.txt, DIR/oxts/SSSS.txt (optional image_02/, image_03/);
//  - VDO-SLAM / DynoSAM: pose_gt.txt, object_pose.txt, times.txt, object_category.txt in DIR/gt/SSSS/,
//    DIR/SSSS/ or DIR/ itself.
// Camera poses come from pose_gt.txt when present, else from oxts through the calibration chain.
// Objects come from label_02 (with their box sizes) when present, else from object_pose.txt with a
// typical size per category. Object ids follow VDO-SLAM: object_id = track_id + 1.

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "data/ground_truth.h"
#include "data/kitti_tracking.h"

namespace dslam {

struct KittiObjectTrack {
  int object_id = 0;
  std::string category = "VEHICLE";
  std::string type;  // KITTI type when known
  double h = 0, w = 0, l = 0;
  bool size_from_labels = true;
  std::map<int, SE3> T_camera_object;  // per frame in which it is labelled
};

struct KittiGroundTruthSequence {
  std::string name;
  double frame_rate_hz = 10.0;  // KITTI records at 10 Hz (times.txt of VDO-SLAM uses 0.05 s steps)
  std::vector<SE3> T_world_camera;
  std::map<int, KittiObjectTrack> objects;
  std::optional<KittiCalibration> calibration;
  std::vector<std::string> sources;  // files read, for the run record
};

// Throws std::runtime_error naming the missing or malformed file.
KittiGroundTruthSequence LoadKittiGroundTruth(const std::string& dir, const std::string& seq);

// The evaluation's ground truth for the first `num_frames` frames: camera poses, object poses and
// centroids (docs/design.md §10: (X, Y - h/2, Z) in the box frame). An object counts as observed in frame k
// when it is labelled there, its centroid is closer to the camera than `object_max_range_m` and
// `visible(k, object_id)` says the sensor saw it (e.g. its instance mask is large enough).
GroundTruth ToGroundTruth(const KittiGroundTruthSequence& gt, int num_frames, double object_max_range_m,
                          const std::function<bool(int, int)>& visible);
// The same in two steps, for a run that learns what it saw frame by frame: every object unobserved, then
// ObserveFrame(k, ...) for each frame k in turn marks the objects observed in it as ToGroundTruth does.
GroundTruth ToUnobservedGroundTruth(const KittiGroundTruthSequence& gt, int num_frames);
void ObserveFrame(int frame, double object_max_range_m, const std::function<bool(int, int)>& visible, GroundTruth* gt);

}  // namespace dslam
