#pragma once
// A LiDAR-only reference for runs on recordings without ground truth (`dslam lidar-check`): the ego-motion
// from registering consecutive scans on their static points (ground and structure, not the object
// clusters), and each object cluster tracked from scan to scan, its motion from registering its points
// and its speed from that motion. No camera image is used: it checks what the camera pipeline estimated.

#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "geometry/pinhole_camera.h"
#include "geometry/se3.h"
#include "lidar/lidar_masks.h"
#include "lidar/scan_registration.h"

namespace dslam {

// Point to plane on static structure, 0.3 m voxels (finer ones leave each point's neighbours on its own scan
// line, whose pattern pulls the motion towards zero), the closest 70 % of the pairs kept each iteration (parts
// of vehicles too small to be clusters, leaves, returns that only one scan has). Measured on the real traffic
// frames: generalized ICP returned its starting guess in most scan pairs, so the path followed the guess
// (6.1 m from standing still, 9.1 m from constant velocity); this setting gives the same path from either.
ScanRegistrationParams EgoRegistration();
// An object's own points, not thinned, within 0.4 m.
ScanRegistrationParams ObjectRegistration();

struct LidarReferenceParams {
  LidarMaskParams clusters;  // the objects: the same segmentation (and field of view) as the mask source
  ScanRegistrationParams ego = EgoRegistration();
  ScanRegistrationParams object = ObjectRegistration();
  double association_gate_m = 1.5;  // a cluster's centroid moves at most this far between scans
  // Per-scan speeds are noisy (a few centimetres of registration error is 0.3 m/s at 10 Hz): the reference
  // speed of a frame is the norm of the mean velocity over this many scans centred on it.
  int speed_window_frames = 5;
  double frame_interval_s = 0.1;
  void validate() const;
};

struct LidarTrackSample {
  int frame = 0;
  int track_id = 0;
  Vec3 centroid_camera = Vec3::Zero();  // of its points, in this frame's camera
  int points = 0;
  double extent_m = 0.0;                 // its footprint's diagonal (a car: 3-5 m; a pole: under 1 m)
  cv::Rect box;                          // its mask's box in the image
  bool has_speed = false;                // false on a track's first scan
  Vec3 velocity_world_mps = Vec3::Zero();  // over the previous scan, in the first camera's frame
  double speed_mps = 0.0;                // windowed (see speed_window_frames)
};

struct LidarReference {
  std::vector<SE3> T_world_camera;  // world = the first camera
  std::vector<LidarTrackSample> samples;
  std::vector<double> ego_rms_m;  // registration residual per scan pair (0 for the first)
  // Per scan pair (0 for the first): how far the pair registered forwards and backwards disagree, metres.
  std::vector<double> ego_step_disagreement_m;
};

class LidarReferenceBuilder {
 public:
  LidarReferenceBuilder(const LidarReferenceParams& params, const PinholeCamera& camera);
  // Scans in frame order.
  void add(const std::vector<Eigen::Vector3f>& points_camera, const Eigen::Vector3f& lidar_origin_camera,
           const Eigen::Vector3f& lidar_up_camera);
  LidarReference finish();

 private:
  struct Cluster {
    Eigen::Vector3f centroid = Eigen::Vector3f::Zero();  // of its points in the camera's view
    // The same object in the whole scan, for its motion: cut at the image's edge, its points in view
    // would move with the edge as the car drives past, and its speed with them.
    std::vector<Eigen::Vector3f> motion_points;
    Eigen::Vector3f motion_centroid = Eigen::Vector3f::Zero();
    int track_id = 0;
  };
  Vec3 ObjectDisplacement(const Cluster& previous, const std::vector<Eigen::Vector3f>& points,
                          const Eigen::Vector3f& centroid, const Eigen::Isometry3d& T_curr_prev) const;

  LidarReferenceParams params_;
  PinholeCamera camera_;
  LidarReference reference_;
  std::vector<Eigen::Vector3f> previous_static_;
  std::vector<Cluster> previous_clusters_;
  int next_track_id_ = 1;
};

}  // namespace dslam
