#pragma once
// Turns a simulated world (true camera path, static points, rigid objects) into noisy measurements
// (3D points in the camera frame, odometry increments) plus ground truth, as DESIGN.md §5 describes.

#include <cstdint>
#include <map>
#include <optional>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "data/sequence.h"
#include "geometry/pinhole_camera.h"
#include "simulation/shapes.h"

namespace dslam {

struct SensorModel {
  PinholeCamera camera;
  double min_depth_m = 1.0;
  double static_max_range_m = 40.0;
  double object_max_range_m = 22.0;  // objects farther than this (centroid distance) are not seen
  int min_object_points = 6;         // fewer visible points: the object is not detected
};

struct SimNoise {
  double point_sigma_m = 0.02;  // per axis
  double odom_translation_fraction = 0.05;
  double odom_rotation_fraction = 0.10;
  double odom_translation_floor_m = 0.001;
  double odom_rotation_floor_rad = 0.01 * kDegToRad;
  void validate() const;
};

struct SimObject {
  int object_id = 0;
  std::string category = "VEHICLE";
  std::vector<SurfacePoint> surface;
  Vec3 centroid_body = Vec3::Zero();
  std::map<int, SE3> L_world_object;  // pose per frame in which the object exists
  std::set<int> occluded_frames;    // frames in which something hides it completely
  std::optional<Vec3> box_lwh;      // when the object is a KITTI-convention box: length, width, height
};

struct SimWorld {
  std::string name;
  double frame_rate_hz = 10.0;
  std::vector<SE3> T_world_camera;  // any world frame; the output is re-expressed in camera 0
  std::vector<Vec3> static_points_world;
  std::vector<SimObject> objects;
};

// An odometry increment with DESIGN.md §5 noise: per-axis sigmas proportional to the step (with floors),
// the true increment perturbed on the right.
OdometryMeasurement NoisyOdometry(const SE3& T_prev_curr_true, const SimNoise& noise, std::mt19937_64& rng);

Sequence SimulateSensor(const SimWorld& world, const SensorModel& sensor, const SimNoise& noise, uint64_t seed);

}  // namespace dslam
