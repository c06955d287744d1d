#pragma once
// The error metrics of docs/design.md §9, computed from plain inputs so that each can be checked by hand.

#include <map>
#include <optional>
#include <utility>
#include <vector>

#include "geometry/se3.h"

namespace dslam {

// An object is "moving" over a frame pair when its true centroid speed reaches this.
constexpr double kMovingSpeedThresholdMps = 1.0;
// Below this camera path length, relative errors are replaced by mean absolute per-step errors.
constexpr double kMinPathForRelativeErrorM = 1.0;

struct CameraMetrics {
  double path_length_m = 0.0;
  std::optional<double> rte_pct;         // relative translation error
  std::optional<double> rre_deg_per_m;   // relative rotation error
  std::optional<double> mean_step_te_m;  // only when the path is shorter than 1 m
  std::optional<double> mean_step_re_deg;
  double ate_m = 0.0;  // RMSE of positions, no alignment
  // Mean normalised estimation error squared of the camera steps T[k-1]^-1 T[k] that came with a covariance
  // (EstimateSink::cameraStepCovariance): 6 when the reported covariance is honest (larger: overconfident).
  std::optional<double> camera_step_nees;
};

// The camera metrics accumulated pose by pose in frame order, so that a long run keeps no trajectory.
class CameraMetricsAccumulator {
 public:
  // `step_covariance`: of the estimated step from the previous pose to this one, when known.
  void add(const SE3& T_world_camera_gt, const SE3& T_world_camera_est, const Mat6* step_covariance = nullptr);
  int poses() const { return poses_; }
  CameraMetrics result() const;

 private:
  int poses_ = 0;
  SE3 gt_prev_, est_prev_;
  double path_length_m_ = 0.0, sum_t_ = 0.0, sum_r_deg_ = 0.0, sum_sq_ate_ = 0.0;
  double sum_nees_ = 0.0;
  int nees_steps_ = 0;
};

// A camera step's error e^T Cov^-1 e, e = [t_est - t_gt; Log(R_gt^T R_est)] (the step's translation in its
// first camera, the rotation perturbed on the right); nullopt when the covariance is not positive definite.
std::optional<double> CameraStepNees(const SE3& step_gt, const SE3& step_est, const Mat6& covariance);

// Poses per frame; both vectors must have the same size (throws std::invalid_argument otherwise).
// `step_covariance`: of the estimated steps into the frames it holds (CameraMetrics::camera_step_nees).
CameraMetrics ComputeCameraMetrics(const std::vector<SE3>& T_world_camera_gt, const std::vector<SE3>& T_world_camera_est,
                                   const std::map<int, Mat6>& step_covariance = {});

// RSE (%) = 100 * sum |p_est - p_gt| / sum |p_gt| over observations, points in the observing camera's frame.
// Pairs are (p_est, p_gt); nullopt when empty.
std::optional<double> ComputeRsePct(const std::vector<std::pair<Vec3, Vec3>>& p_est_gt_camera);

class RseAccumulator {
 public:
  void add(const Vec3& p_est_camera, const Vec3& p_gt_camera);
  std::optional<double> result() const;

 private:
  int pairs_ = 0;
  double sum_error_m_ = 0.0, sum_gt_m_ = 0.0;
};

// One object over one ground-truth frame pair k-1 -> k.
struct ObjectPairSample {
  int object_id = 0;
  int frame = 0;
  SE3 H_world_gt;
  SE3 L_world_object_gt_prev;  // ground-truth object pose at k-1, for the body-frame comparison
  double speed_gt_mps = 0.0;  // of the pair itself: what OMSE compares the estimate with
  // The object's centroid speed averaged over about a second centred on the pair (net displacement over
  // time): what decides whether the pair is moving. KITTI's box labels jitter by centimetres a frame, so a
  // parked car's single pair can pass 1 m/s; over a second the jitter cancels.
  double window_speed_gt_mps = 0.0;
  // Enough of the same surface seen in both frames to measure the motion (GroundTruth::measurable_frames);
  // absent where the ground truth cannot tell.
  std::optional<bool> measurable;
  bool estimated = false;
  SE3 H_world_est;
  double speed_est_mps = 0.0;
  bool est_dynamic = false;
  Mat6 covariance_est = Mat6::Zero();  // of the estimate (ObjectMotionEstimate::covariance)
  Vec3 anchor_est = Vec3::Zero();      // the point that covariance's tangent is about
  double speed_sigma_est_mps = 0.0;

  bool gtMoving() const { return window_speed_gt_mps >= kMovingSpeedThresholdMps; }
};

struct ObjectMetrics {
  int gt_pairs = 0;
  int gt_moving_pairs = 0;
  std::optional<int> measurable_moving_pairs;  // when the ground truth tells which pairs are measurable
  int estimated_pairs = 0;
  int moving_pairs_estimated = 0;
  int static_pairs_estimated = 0;
  std::optional<double> omte_pct;
  std::optional<double> omre_deg_per_m;
  std::optional<double> omse_pct;
  std::optional<double> me_t_m;
  std::optional<double> me_r_deg;
  std::optional<double> speed_err_mps;
  std::optional<double> object_coverage;             // moving pairs estimated / moving ground-truth pairs
  std::optional<double> object_coverage_measurable;  // the same over the measurable moving pairs
  // Mean normalised estimation error squared of the moving pairs' motions, e^T Cov^-1 e over the 6-dof
  // tangent of the covariance: 6 when the reported covariance is honest (larger: overconfident).
  std::optional<double> motion_nees;
  std::optional<double> static_mean_speed_mps;    // over estimated static pairs
  std::optional<double> static_false_dynamic_frac;
};

// Body-frame motion error E = H_body_gt^-1 * H_body_est with H_body = L_prev^-1 * H_world * L_prev.
SE3 ObjectMotionError(const ObjectPairSample& s);

// The object metrics accumulated sample by sample, in any order.
class ObjectMetricsAccumulator {
 public:
  // A ground-truth pair and, when it has one, its estimate.
  void add(const ObjectPairSample& sample);
  // The same in two steps, for a run that knows its pairs before their estimates are final: every
  // pair once (its estimate fields unused), and later the estimated ones.
  void addPair(const ObjectPairSample& pair);
  void addEstimate(const ObjectPairSample& sample);
  ObjectMetrics result() const;

 private:
  ObjectMetrics counts_;  // the counters; the ratios are formed in result()
  double sum_e_t_ = 0.0, sum_e_r_deg_ = 0.0, sum_gt_t_ = 0.0, sum_speed_err_ = 0.0, sum_speed_gt_ = 0.0;
  double sum_static_speed_ = 0.0;
  int false_dynamic_ = 0;
  int measurable_moving_estimated_ = 0;
  double sum_nees_ = 0.0;
  int nees_pairs_ = 0;
};

ObjectMetrics ComputeObjectMetrics(const std::vector<ObjectPairSample>& samples);

// The estimate's error e^T Cov^-1 e in its covariance's tangent ([translation; rotation] of H about the anchor,
// the rotation perturbed on the right); nullopt when the sample has no positive-definite covariance.
std::optional<double> MotionNees(const ObjectPairSample& sample);

}  // namespace dslam
