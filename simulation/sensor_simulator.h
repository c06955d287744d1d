#pragma once
// Turns a simulated world (true camera path, static points, rigid objects) into noisy measurements
// (3D points in the camera frame, odometry increments) plus ground truth, as docs/design.md §10 describes.

#include <cstdint>
#include <map>
#include <memory>
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

// An odometry increment with the simulated noise (docs/design.md §10): per-axis sigmas proportional to the step (with floors),
// the true increment perturbed on the right.
OdometryMeasurement NoisyOdometry(const SE3& T_prev_curr_true, const SimNoise& noise, std::mt19937_64& rng);

// Measures a world frame by frame, so that a long run holds one frame's measurement at a time. The
// ground truth (poses, points, boxes; re-expressed in camera 0) exists from the start, except which
// frames saw each object: `observed_frames` grows as frames are made.
class SensorSimulator {
 public:
  // Throws std::invalid_argument for bad noise, fewer than 2 frames or object poses outside the sequence.
  SensorSimulator(SimWorld world, const SensorModel& sensor, const SimNoise& noise, uint64_t seed);
  ~SensorSimulator();
  SensorSimulator(SensorSimulator&&) noexcept;

  const std::string& name() const { return name_; }
  double frameRateHz() const { return frame_rate_hz_; }
  int numFrames() const { return static_cast<int>(gt_.T_world_camera.size()); }
  int framesMade() const { return next_frame_; }
  bool done() const { return next_frame_ >= numFrames(); }
  const GroundTruth& groundTruth() const { return gt_; }
  // Measures the next frame (std::logic_error when done()) and records the objects it saw.
  FrameMeasurement next();
  // The remaining frames and the ground truth as one sequence; the simulator is spent after it.
  Sequence drain();

 private:
  class StaticPointIndex;
  struct Body {  // what the sensor needs of an object besides its ground-truth poses
    int object_id;
    int first_frame, last_frame;
    std::vector<SurfacePoint> surface;
    std::set<int> occluded_frames;
    std::vector<size_t> seen_last_frame;  // surface points measured in the previous frame (sorted)
  };
  std::string name_;
  double frame_rate_hz_;
  SensorModel sensor_;
  SimNoise noise_;
  std::mt19937_64 rng_;
  GroundTruth gt_;
  std::vector<Body> bodies_;  // in the world's object order (the order noise is drawn in)
  std::unique_ptr<StaticPointIndex> static_index_;
  int next_frame_ = 0;
};

// All frames at once (short sequences, tests).
Sequence SimulateSensor(SimWorld world, const SensorModel& sensor, const SimNoise& noise, uint64_t seed);

}  // namespace dslam
