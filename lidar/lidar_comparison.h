#pragma once
// A run on a recording without ground truth, checked against the LiDAR-only reference
// (lidar/lidar_reference.h): the camera's path against the scans' registration, and each object's speed
// against the speed of the LiDAR cluster at the same place.

#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "geometry/se3.h"
#include "lidar/lidar_reference.h"

namespace dslam {

// One row of a run's object_speeds.csv.
struct RunObjectRow {
  int frame = 0, object_id = 0;
  bool moving = false;  // reported moving (is_dynamic)
  double speed_mps = 0.0;
  std::optional<Vec3> centroid_camera;
  std::optional<cv::Rect> box;  // its mask's box in the image, when the run wrote it
};

struct LidarCheckParams {
  double vehicle_max_distance_m = 25.0;  // vehicles nearer than this are scored
  int min_track_frames = 10;             // tracked by the LiDAR in at least this many frames (within range)
  double vehicle_min_extent_m = 1.5;     // a cluster this wide or long (median over its track) is a vehicle
  // A run's row is the LiDAR cluster whose mask's box overlaps its own most, by at least this IoU (a long
  // truck's visible part has its centroid metres from the whole cluster's); rows without a box, or without
  // such a cluster, take the cluster whose centroid is nearest within match_gate_m.
  double match_min_box_iou = 0.5;
  double match_gate_m = 2.5;
  // A LiDAR cluster slower than this (windowed) is standing: twice the speeds the reference gives standing
  // vehicles (0.05-0.13 m/s on the real traffic frames), and well under creeping traffic, which a run
  // reporting moving from 0.5 m/s may call either.
  double standing_speed_mps = 0.25;
  // A vehicle's frame is scored only where the camera sees it: its mask's box covers at least this fraction
  // of the image (0.05 %: 15 x 15 pixels of a KITTI frame), as the mask scores count objects. Out of view,
  // hidden behind nearer objects, or a sliver at the image's edge, it cannot be estimated from the images.
  double vehicle_min_box_fraction = 0.0005;
  int image_width = 0, image_height = 0;  // the camera's image (0: any box with pixels counts)
};

// The reference's own frame-to-frame noise, from each scan pair registered both ways: the median
// disagreement a step, and the sum over the path in % of its length (the floor under rte_pct below: a
// camera that moved exactly as the car did would still show about this much).
struct LidarReferenceNoise {
  double median_step_m = 0.0;
  double summed_pct_of_path = 0.0;
};
LidarReferenceNoise ReferenceNoise(const LidarReference& reference);

struct LidarCheckReport {
  // Camera against the LiDAR registration (world = the first camera for both).
  int frames = 0;
  double path_length_m = 0.0;
  double end_error_m = 0.0, end_error_pct = 0.0;  // of the last pose's position; % of the path length
  double rte_pct = 0.0;                           // frame to frame, % of the distance travelled
  double rre_deg_per_m = 0.0;
  double mean_step_rotation_error_deg = 0.0;
  LidarReferenceNoise reference_noise;
  struct Vehicle {
    int track_id = 0;
    int frames = 0;             // LiDAR frames within range
    int frames_with_speed = 0;  // of those, frames where the run gave the object matched there a speed
    double coverage = 0.0;
    double median_lidar_speed_mps = 0.0;
    std::optional<double> median_speed_difference_mps;
    int moving_while_standing = 0;  // frames the run reported it moving while the LiDAR has it standing
  };
  std::vector<Vehicle> vehicles;  // tracked >= min_track_frames within range, vehicle-sized
  int moving_rows = 0;                 // run rows reported moving
  int moving_rows_without_cluster = 0;  // of those, at no LiDAR cluster (structure, or nothing)
  int moving_rows_on_standing = 0;      // of those, at a LiDAR cluster that stands (any cluster)
};

LidarCheckReport CompareWithLidar(const LidarReference& reference, const std::vector<SE3>& T_world_camera_run,
                                  const std::vector<RunObjectRow>& rows, const LidarCheckParams& params);

}  // namespace dslam
