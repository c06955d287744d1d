#include "frontend/dynamic_object_classifier.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <stdexcept>
#include <unordered_map>
#include <vector>

#include "geometry/velocity.h"

namespace dslam {
namespace {
// Pairs of the same track ids in two observation lists.
void MatchTracks(const std::vector<PointObservation>& prev, const std::vector<PointObservation>& curr,
                 std::vector<Vec3>* prev_pts, std::vector<Vec3>* curr_pts) {
  std::unordered_map<int64_t, const Vec3*> by_id;
  for (const auto& p : prev) by_id[p.track_id] = &p.p_camera;
  for (const auto& c : curr) {
    const auto it = by_id.find(c.track_id);
    if (it == by_id.end()) continue;
    prev_pts->push_back(*it->second);
    curr_pts->push_back(c.p_camera);
  }
}
// Until an object's window holds half its length, one transition this many times faster than the speed
// threshold (and significant, over at least min_static_inliers tracks) is reported moving: an oncoming car
// seen for a few frames gets its speed. A fit on fewer tracks (a car entering the view with a few points)
// has residuals too few to tell its error: one such fit put a parked car on rendered KITTI 0000 at 2.3 m/s.
// A small mask (a far car, or a sliver of one hidden or leaving the view) gives a fit whose error its
// speed alone does not show, so there the speed less its bound must be that fast.
constexpr double kClearMotionFactor = 3.0;
// Floor of a displacement's standard deviation: unmodelled effects (and exact synthetic data).
constexpr double kMinDisplacementSigmaM = 1e-3;

// Per-axis sigma of the jitter of an object's position over its `n` last transitions: the spread of
// its positions (the displacements summed from the first), less what the point and camera noise give.
// Labels jitter slowly as well as from frame to frame, so the positions' spread, not the displacements'
// size, tells how far a point of the object strays from where the map holds it. A still object's spread
// passes twice the noise's in at most 6 % of windows (chi-square, 6 to 15 degrees of freedom); below
// that no jitter is seen, so the noise alone does not widen a truly parked car's points.
double JitterSigma(const std::deque<Vec3>& displacement, const std::deque<double>& variance_m2, int n) {
  n = std::min<int>(n, static_cast<int>(displacement.size()));
  if (n <= 0) return 0.0;
  std::vector<Vec3> positions(1, Vec3::Zero());
  double noise_m2 = 0.0;
  for (size_t i = displacement.size() - n; i < displacement.size(); ++i) {
    positions.push_back(positions.back() + displacement[i]);
    if (std::isfinite(variance_m2[i])) noise_m2 += variance_m2[i] / 2.0;  // a displacement's is two positions'
  }
  noise_m2 /= n;
  Vec3 mean = Vec3::Zero();
  for (const Vec3& p : positions) mean += p;
  mean /= static_cast<double>(positions.size());
  double spread_m2 = 0.0;
  for (const Vec3& p : positions) spread_m2 += (p - mean).squaredNorm();
  spread_m2 /= 3.0 * static_cast<double>(positions.size() - 1);
  return spread_m2 > 2.0 * noise_m2 ? std::sqrt(spread_m2 - noise_m2) : 0.0;
}

double RmsSpread(const std::vector<Vec3>& pts) {
  Vec3 mean = Vec3::Zero();
  for (const auto& p : pts) mean += p;
  mean /= static_cast<double>(pts.size());
  double sum_sq = 0.0;
  for (const auto& p : pts) sum_sq += (p - mean).squaredNorm();
  return std::sqrt(sum_sq / static_cast<double>(pts.size()));
}
}  // namespace

void ClassifierParams::validate() const {
  if (!(dynamic_speed_threshold_mps > 0.0))
    throw std::invalid_argument("classifier.dynamic_speed_threshold_mps must be positive");
  if (!(report_speed_threshold_mps > 0.0))
    throw std::invalid_argument("classifier.report_speed_threshold_mps must be positive");
  if (!(static_test_chi2 > 0.0)) throw std::invalid_argument("classifier.static_test_chi2 must be positive");
  if (min_static_transitions < 1) throw std::invalid_argument("classifier.min_static_transitions must be >= 1");
  if (min_static_inliers < 3) throw std::invalid_argument("classifier.min_static_inliers must be >= 3");
  if (!(small_object_area_pct >= 0.0 && small_object_area_pct <= 100.0))
    throw std::invalid_argument("classifier.small_object_area_pct must be in [0, 100]");
  if (!(motion_window_s >= 0.0 && motion_window_s <= 10.0))
    throw std::invalid_argument("classifier.motion_window_s must be in [0, 10] seconds");
}

DynamicObjectClassifier::DynamicObjectClassifier(const ClassifierParams& params, double frame_rate_hz)
    : params_(params), frame_rate_hz_(frame_rate_hz) {
  params_.validate();
  window_transitions_ = std::max(1, static_cast<int>(std::lround(params_.motion_window_s * frame_rate_hz_)));
}

CameraMotionEstimate DynamicObjectClassifier::cameraMotion(const FrameMeasurement& prev,
                                                          const FrameMeasurement& curr) const {
  std::vector<Vec3> prev_pts, curr_pts;
  MatchTracks(prev.static_points, curr.static_points, &prev_pts, &curr_pts);
  if (static_cast<int>(prev_pts.size()) >= params_.min_static_inliers) {
    // z_prev = T_prev_curr * z_curr for static points.
    const auto fit = AlignRigidRansac(curr_pts, prev_pts, params_.static_ransac);
    if (fit && fit->num_inliers >= params_.min_static_inliers) {
      std::vector<Vec3> inliers;
      double sum_sq = 0.0;
      for (size_t i = 0; i < prev_pts.size(); ++i) {
        if (!fit->is_inlier[i]) continue;
        sum_sq += (prev_pts[i] - fit->transform * curr_pts[i]).squaredNorm();
        inliers.push_back(prev_pts[i]);
      }
      const double n = static_cast<double>(inliers.size());
      const double sigma = std::sqrt(sum_sq / std::max(1.0, 3.0 * n - 6.0));
      return {fit->transform, true, sigma / std::sqrt(n), sigma / (std::sqrt(n) * std::max(0.1, RmsSpread(inliers)))};
    }
  }
  if (curr.odometry) return {curr.odometry->T_prev_curr, false, curr.odometry->sigma.head<3>().norm() / std::sqrt(3.0),
                             curr.odometry->sigma.tail<3>().norm() / std::sqrt(3.0)};
  // Nothing tells the camera motion: assume still, and let only the speed threshold decide.
  return {SE3::Identity(), false, std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
}

double DynamicObjectClassifier::transitionPeriods(const FrameMeasurement& prev, const FrameMeasurement& curr) const {
  // No stamps, stamps not increasing, or jitter: the nominal period.
  const double periods = StepPeriods(prev.t_ns, curr.t_ns, 1.0 / frame_rate_hz_);
  return periods > kGapPeriods ? periods : 1.0;
}

std::optional<ObjectMotionTest> DynamicObjectClassifier::testObjectMotion(const ObjectObservation& prev,
                                                                          const ObjectObservation& curr,
                                                                          const CameraMotionEstimate& camera,
                                                                          double periods) const {
  // The image front-end has fitted this object's motion already (against its own camera motion); other
  // sources get the same fit here, against `camera`.
  std::optional<ObjectMotionFit> fit = curr.motion_fit;
  if (!fit) {
    std::vector<Vec3> prev_pts, curr_pts;
    MatchTracks(prev.points, curr.points, &prev_pts, &curr_pts);
    for (auto& p : curr_pts) p = camera.T_prev_curr * p;  // into camera k-1: what remains is the object's own motion
    const auto ransac = AlignRigidRansac(prev_pts, curr_pts, params_.object_ransac);
    if (!ransac) return std::nullopt;
    fit = SummariseMotionFit(ransac->transform, prev_pts, curr_pts, ransac->is_inlier);
  }
  if (fit->num_inliers < params_.object_ransac.min_inliers) return std::nullopt;
  const double n = static_cast<double>(fit->num_inliers);
  const Vec3 centroid = fit->centroid_camera_prev;
  const double sum_sq = fit->residual_sq_sum_m2;
  ObjectMotionTest test;
  const Vec3 displacement = ObjectVelocityPerFrame(fit->H_camera_prev, centroid);
  test.speed_mps = SpeedMps(displacement, frame_rate_hz_ / periods);
  // Per-axis variance of the centroid displacement if the object were static: the object's own
  // point noise (from the fit's residuals) plus the camera motion's uncertainty at that distance.
  const double sigma_points_sq = sum_sq / std::max(1.0, 3.0 * n - 6.0) / n;
  const double camera_sq = std::pow(camera.translation_sigma_m, 2) + std::pow(camera.rotation_sigma_rad * centroid.norm(), 2);
  const double variance = sigma_points_sq + camera_sq + kMinDisplacementSigmaM * kMinDisplacementSigmaM;
  test.chi2 = std::isfinite(variance) && variance > 0.0 ? displacement.squaredNorm() / variance : 0.0;
  test.significant = test.chi2 > params_.static_test_chi2;
  test.displacement_camera_prev = displacement;
  test.variance_m2 = variance;
  test.inliers = fit->num_inliers;
  return test;
}

ReportedMotion DynamicObjectClassifier::reportOverWindow(const Window& window) const {
  // Supported only once the window holds half its length: a car entering the view (or back from an
  // occlusion) with a few tracks gets no report from one or two noisy fits, unless it is clearly moving.
  const int n = static_cast<int>(window.displacement.size());
  if (2 * n < window_transitions_) return window.last_clearly_moving ? ReportedMotion::kMoving : ReportedMotion::kUnsupported;
  // Two statistics of the window's displacements, each blind where the other sees:
  //  - their sum (the net displacement): a parked car's jitter cancels in it, but one wrong fit (a
  //    re-acquired track, possibly backwards) weighs as much as the whole motion;
  //  - their per-axis median (the typical displacement), with most transitions moving that way
  //    significantly: one wrong fit does not move it, but a jitter that alternates does.
  // Moving: both agree, or the typical displacement alone is clearly moving (far above any jitter).
  Vec3 sum = Vec3::Zero(), median;
  double variance = 0.0;
  for (int i = 0; i < n; ++i) sum += window.displacement[i], variance += window.variance_m2[i];
  for (int axis = 0; axis < 3; ++axis) {
    std::vector<double> values;
    for (const Vec3& d : window.displacement) values.push_back(d[axis]);
    std::nth_element(values.begin(), values.begin() + n / 2, values.end());
    median[axis] = n % 2 ? values[n / 2]
                         : 0.5 * (values[n / 2] + *std::max_element(values.begin(), values.begin() + n / 2));
  }
  const double step_m = params_.report_speed_threshold_mps / frame_rate_hz_;
  // An infinite variance (no camera motion known) leaves the speeds alone to decide.
  const auto significant = [&](double d_m, double var_m2) {
    return !std::isfinite(var_m2) || d_m * d_m > params_.static_test_chi2 * var_m2;
  };
  const bool net_moving = sum.norm() >= n * step_m && significant(sum.norm(), variance);
  bool typical_moving = false;
  if (median.norm() >= step_m) {
    const Vec3 direction = median.normalized();
    int along = 0;
    for (int i = 0; i < n; ++i) {
      const double d = window.displacement[i].dot(direction);
      along += d >= step_m && significant(d, window.variance_m2[i]);
    }
    typical_moving = 2 * along > n;
  }
  const bool clearly = typical_moving && median.norm() >= kClearMotionFactor * step_m;
  return (net_moving && typical_moving) || clearly ? ReportedMotion::kMoving : ReportedMotion::kStanding;
}

void DynamicObjectClassifier::label(const FrameMeasurement& prev, FrameMeasurement* curr) {
  const CameraMotionEstimate camera = cameraMotion(prev, *curr);
  // Across a gap (frames dropped or lost) a displacement spans several periods: speeds are over the step, and
  // the window keeps displacements per period (the chi-square tests, a ratio of the two, do not change).
  const double periods = transitionPeriods(prev, *curr);
  std::map<int, int> streaks;
  std::map<int, Window> windows;
  for (auto& obj : curr->objects) {
    bool still = false;
    std::optional<ReportedMotion> report;
    const Window* window_now = nullptr;
    for (const auto& before : prev.objects) {
      if (before.object_id != obj.object_id) continue;
      Window window = windows_.count(obj.object_id) ? windows_.at(obj.object_id) : Window{};
      if (const auto test = testObjectMotion(before, obj, camera, periods)) {
        still = test->speed_mps < params_.dynamic_speed_threshold_mps && !test->significant;
        window.displacement.push_back(R_first_camera_ * test->displacement_camera_prev / periods);
        const bool small = obj.mask_area_frac && 100.0 * *obj.mask_area_frac < params_.small_object_area_pct;
        const double margin_mps =
            small ? std::sqrt(params_.static_test_chi2 * test->variance_m2) * frame_rate_hz_ / periods : 0.0;
        window.last_clearly_moving =
            test->significant &&
            test->speed_mps - margin_mps >= kClearMotionFactor * params_.report_speed_threshold_mps &&
            test->inliers >= params_.min_static_inliers;
        window.variance_m2.push_back(test->variance_m2 / (periods * periods));
        while (static_cast<int>(window.displacement.size()) > window_transitions_) {
          window.displacement.pop_front();
          window.variance_m2.pop_front();
        }
      }
      if (!window.displacement.empty()) report = reportOverWindow(window);
      window_now = &(windows[obj.object_id] = std::move(window));
    }
    const auto it = static_streak_.find(obj.object_id);
    const int streak = still ? (it == static_streak_.end() ? 0 : it->second) + 1 : 0;
    streaks[obj.object_id] = streak;
    obj.is_dynamic = streak < params_.min_static_transitions;
    obj.reported = !obj.is_dynamic ? ReportedMotion::kStanding : report.value_or(ReportedMotion::kUnsupported);
    obj.jitter_sigma_m = !obj.is_dynamic && window_now
                             ? JitterSigma(window_now->displacement, window_now->variance_m2, streak)
                             : 0.0;
  }
  static_streak_ = std::move(streaks);  // objects not seen in this frame start over
  windows_ = std::move(windows);
  R_first_camera_ = R_first_camera_ * camera.T_prev_curr.rotationMatrix();
}

}  // namespace dslam

namespace dslam {
void LabelDynamicObjects(const ClassifierParams& params, double frame_rate_hz, std::vector<FrameMeasurement>* frames) {
  DynamicObjectClassifier classifier(params, frame_rate_hz);
  for (size_t k = 1; k < frames->size(); ++k) classifier.label((*frames)[k - 1], &(*frames)[k]);
}
}  // namespace dslam
