#pragma once
// What a frame source (simulator, dataset reader, DDS) hands the pipeline for one frame:
// small value structs, timestamps in integer nanoseconds.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "geometry/se3.h"

namespace dslam {

// A tracked 3D point seen in one frame, in that frame's camera coordinates (back-projected depth).
struct PointObservation {
  int64_t track_id = 0;  // the same physical point keeps its id over frames
  Vec3 p_camera = Vec3::Zero();
};

// An image front-end's fit of one object's own motion over k-1 -> k: 3D-3D RANSAC on its tracks with
// the camera motion removed, in camera k-1 coordinates. Its inliers are the object's points that carry
// on from k-1 (the front-end ends its outlier tracks). The static/dynamic test and the graph builder
// start from it instead of fitting the same tracks again.
struct ObjectMotionFit {
  SE3 H_camera_prev;            // p_{k-1} -> T_prev_curr * p_k, both in camera k-1 coordinates
  Vec3 centroid_camera_prev = Vec3::Zero();  // of the inliers at k-1
  int num_inliers = 0;
  double residual_sq_sum_m2 = 0.0;  // sum over inliers of |T_prev_curr * p_k - H * p_{k-1}|^2
};

enum class ReportedMotion { kMoving, kStanding, kUnsupported };

// An object's bounding box in the image, pixels (x, y: its top-left corner).
struct ImageBox {
  int x = 0, y = 0, width = 0, height = 0;
};

// Points that fall inside one instance mask.
struct ObjectObservation {
  int object_id = 0;
  std::vector<PointObservation> points;
  // Set by the front-end's scene-flow test over the transition from the previous frame; an object
  // first seen in this frame stays dynamic (it has no previous frame to compare with).
  bool is_dynamic = true;
  // What is reported of it (the classifier's decision over its recent transitions): a dynamic object
  // that is not moving (a parked car whose measurements jitter) keeps its own motion in the estimator
  // but is reported standing, with speed 0; an object whose motion is not yet supported (entering the
  // view, back from an occlusion) is estimated but its motion is not reported at all.
  ReportedMotion reported = ReportedMotion::kMoving;
  // Per-axis sigma of the jitter of a static object's position, m, which all its points share (the
  // classifier's estimate; 0 when none is seen). A replayed or rendered KITTI label moves a parked car by
  // centimetres a frame: too little to call it moving, but its points err together, so as static
  // structure they weigh as one landmark with this sigma, not as many independent ones.
  double jitter_sigma_m = 0.0;
  std::optional<ObjectMotionFit> motion_fit;  // from an image front-end; absent for other sources
  // Share of the image its instance mask covers, 0..1 (an image front-end; absent for other sources).
  // A small mask (a far car, or one mostly hidden or out of view) gives a weaker first fit.
  std::optional<double> mask_area_frac;
  // The box around its instance mask (an image front-end; absent for other sources): with the centroid of
  // its points it tells a user which object of the image a result row is about.
  std::optional<ImageBox> image_box;
};

// Odometry increment T_prev_curr = T_world_camera[k-1]^-1 * T_world_camera[k] with per-axis sigmas.
struct OdometryMeasurement {
  SE3 T_prev_curr;
  Vec6 sigma = Vec6::Constant(0.01);  // [translation m x3; rotation rad x3]
};

// The increment over two consecutive ones (a then b), for a frame dropped between them; the sigmas add
// in quadrature (independent increments, rotation's effect on the translation neglected).
inline OdometryMeasurement Compose(const OdometryMeasurement& a, const OdometryMeasurement& b) {
  return {a.T_prev_curr * b.T_prev_curr, (a.sigma.array().square() + b.sigma.array().square()).sqrt().matrix()};
}

// Steps between frames, by their stamps. A step of more than kGapPeriods frame periods is a gap (frames dropped
// or lost on the way); within it the stamps only jitter (KITTI raw's by a few ms).
constexpr double kGapPeriods = 1.5;
// The step from `prev_t_ns` to `t_ns` in frame periods of `period_s`; 0 when the stamps do not increase.
inline double StepPeriods(int64_t prev_t_ns, int64_t t_ns, double period_s) {
  return t_ns > prev_t_ns ? 1e-9 * static_cast<double>(t_ns - prev_t_ns) / period_s : 0.0;
}

struct FrameMeasurement {
  int frame_index = 0;
  int64_t t_ns = 0;
  std::optional<OdometryMeasurement> odometry;  // absent on the first frame
  // The front-end's own estimate of T_prev_curr (PnP on static points, fused with the odometry): an
  // initial value for the back-end, not a measurement. Absent: the back-end starts from the odometry.
  std::optional<SE3> camera_motion_guess;
  std::vector<PointObservation> static_points;   // background points
  std::vector<ObjectObservation> objects;
};

}  // namespace dslam

namespace dslam {
// Empty when the frame is usable; otherwise a message naming the first bad value
// (non-finite point or odometry, non-positive odometry sigma, duplicate object id).
std::string FindInvalidMeasurement(const FrameMeasurement& frame);
// The same, and the frame must be the `expected_index`-th of its sequence (the back-end's check).
std::string FindInvalidMeasurement(const FrameMeasurement& frame, int expected_index);

// The fit of motion H to the pairs (src[i] at k-1, dst[i] at k, camera k-1 coordinates) summarised over
// its inliers: centroid at k-1, sum of squared residuals, count.
ObjectMotionFit SummariseMotionFit(const SE3& H, const std::vector<Vec3>& src, const std::vector<Vec3>& dst,
                                   const std::vector<bool>& inlier);
}  // namespace dslam
