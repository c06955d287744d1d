#pragma once
// What an estimator hands its result sinks: camera poses, object motions with velocities, and the
// estimated world position of every point observation (for the structure error).

#include <cstdint>
#include <map>
#include <optional>
#include <vector>

#include "data/measurements.h"
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
  // The time the motion spans, from frame-1's stamp to frame's: more than a frame period after dropped
  // frames; 0 when the frames carry no stamps (the nominal period then).
  double step_s = 0.0;
  // Marginal covariance of H from the smoother's information, over the tangent [translation;
  // rotation] of H expressed about the object's anchor (its points' centroid when the motion was
  // created), the rotation perturbed on the right; zero when unknown (batch, or reported standing).
  Mat6 covariance = Mat6::Zero();
  Vec3 anchor_world = Vec3::Zero();  // the point the covariance's tangent is about
  double speed_sigma_mps = 0.0;  // of speed_mps, from `covariance`; 0 when unknown
  // Where the object is in frame `frame`, from its measurement: the centroid of its measured points in
  // that frame's camera, and its box in that image (absent when the source gives no image).
  Vec3 centroid_camera = Vec3::Zero();
  std::optional<ImageBox> image_box;

  // The tracked points' centroid at `frame`: moved rigidly by H from frame - 1.
  Vec3 centroidWorld() const { return H_world * centroid_prev_world; }
  // Per second of the motion's own step; `frame_rate_hz` when the step is unknown.
  Vec3 velocityMps(double frame_rate_hz) const {
    return step_s > 0.0 ? Vec3(velocity_world_per_frame / step_s) : Vec3(velocity_world_per_frame * frame_rate_hz);
  }
};

struct PointEstimate {
  int frame = 0;
  int64_t track_id = 0;
  int object_id = -1;
  Vec3 p_world = Vec3::Zero();
};

struct Estimate {
  std::vector<SE3> T_world_camera;
  std::map<int, Mat6> camera_step_covariance;  // by frame, where the estimator gave one (EstimateSink)
  std::vector<ObjectMotionEstimate> object_motions;  // only transitions that received an estimate
  std::vector<PointEstimate> points;
};

// Receives estimates as they become final (the fixed-lag smoother: when they leave its window),
// cameras in frame order. A result sink (files, DDS) streams them; nothing else keeps them.
class EstimateSink {
 public:
  virtual ~EstimateSink() = default;
  virtual void cameraFinal(int frame, const SE3& T_world_camera) = 0;
  virtual void motionFinal(const ObjectMotionEstimate& motion) = 0;
  virtual void pointFinal(const PointEstimate& point) = 0;
  // Before cameraFinal(frame), when the estimator knows it: the covariance of the camera's step
  // T[frame-1]^-1 T[frame] from its information, over the tangent [translation, in camera frame-1;
  // rotation, perturbed on the right] (backend/window_solver.h). A sink may ignore it.
  virtual void cameraStepCovariance(int /*frame*/, const Mat6& /*covariance*/) {}
};

// Keeps everything it receives, as one Estimate (runs that evaluate at the end).
class CollectingSink : public EstimateSink {
 public:
  void cameraFinal(int, const SE3& T_world_camera) override { estimate.T_world_camera.push_back(T_world_camera); }
  void motionFinal(const ObjectMotionEstimate& motion) override { estimate.object_motions.push_back(motion); }
  void pointFinal(const PointEstimate& point) override { estimate.points.push_back(point); }
  void cameraStepCovariance(int frame, const Mat6& covariance) override {
    estimate.camera_step_covariance[frame] = covariance;
  }
  Estimate estimate;
};

// Hands every estimate to each of its sinks in turn (e.g. files as they become final, and a collection
// for the evaluation at the end); null sinks are left out.
class TeeSink : public EstimateSink {
 public:
  TeeSink() = default;
  TeeSink(EstimateSink* a, EstimateSink* b) { add(a), add(b); }
  void add(EstimateSink* sink) {
    if (sink) sinks_.push_back(sink);
  }
  bool empty() const { return sinks_.empty(); }
  void cameraFinal(int frame, const SE3& T_world_camera) override {
    for (EstimateSink* s : sinks_) s->cameraFinal(frame, T_world_camera);
  }
  void motionFinal(const ObjectMotionEstimate& motion) override {
    for (EstimateSink* s : sinks_) s->motionFinal(motion);
  }
  void pointFinal(const PointEstimate& point) override {
    for (EstimateSink* s : sinks_) s->pointFinal(point);
  }
  void cameraStepCovariance(int frame, const Mat6& covariance) override {
    for (EstimateSink* s : sinks_) s->cameraStepCovariance(frame, covariance);
  }

 private:
  std::vector<EstimateSink*> sinks_;
};

}  // namespace dslam
