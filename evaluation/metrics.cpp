#include "evaluation/metrics.h"

#include <Eigen/Cholesky>

#include <cmath>
#include <stdexcept>

namespace dslam {
namespace {

// e^T Cov^-1 e; nullopt when the covariance is unknown (zero) or not positive definite.
std::optional<double> NormalisedSquare(const Vec6& e, const Mat6& covariance) {
  if (covariance.isZero(0.0)) return std::nullopt;
  const Eigen::LDLT<Mat6> ldlt(covariance);
  if (ldlt.info() != Eigen::Success || !ldlt.isPositive() || (ldlt.vectorD().array() <= 0.0).any()) return std::nullopt;
  return e.dot(ldlt.solve(e));
}

}  // namespace

void CameraMetricsAccumulator::add(const SE3& gt, const SE3& est, const Mat6* step_covariance) {
  sum_sq_ate_ += (gt.translation() - est.translation()).squaredNorm();
  if (poses_ > 0) {
    const SE3 d_gt = gt_prev_.inverse() * gt;
    const SE3 d_est = est_prev_.inverse() * est;
    if (step_covariance)
      if (const std::optional<double> nees = CameraStepNees(d_gt, d_est, *step_covariance)) sum_nees_ += *nees, ++nees_steps_;
    const SE3 e = d_gt.inverse() * d_est;
    path_length_m_ += d_gt.translation().norm();
    sum_t_ += e.translation().norm();
    sum_r_deg_ += e.angle() * kRadToDeg;
  }
  gt_prev_ = gt;
  est_prev_ = est;
  ++poses_;
}

std::optional<double> CameraStepNees(const SE3& step_gt, const SE3& step_est, const Mat6& covariance) {
  Vec6 e;
  e << step_est.translation() - step_gt.translation(), RotationLog(step_gt.rotation().conjugate() * step_est.rotation());
  return NormalisedSquare(e, covariance);
}

CameraMetrics CameraMetricsAccumulator::result() const {
  CameraMetrics m;
  m.path_length_m = path_length_m_;
  if (nees_steps_ > 0) m.camera_step_nees = sum_nees_ / nees_steps_;
  if (poses_ > 0) m.ate_m = std::sqrt(sum_sq_ate_ / static_cast<double>(poses_));
  const double steps = poses_ > 1 ? static_cast<double>(poses_ - 1) : 0.0;
  if (path_length_m_ >= kMinPathForRelativeErrorM) {
    m.rte_pct = 100.0 * sum_t_ / path_length_m_;
    m.rre_deg_per_m = sum_r_deg_ / path_length_m_;
  } else if (steps > 0) {
    m.mean_step_te_m = sum_t_ / steps;
    m.mean_step_re_deg = sum_r_deg_ / steps;
  }
  return m;
}

CameraMetrics ComputeCameraMetrics(const std::vector<SE3>& gt, const std::vector<SE3>& est,
                                   const std::map<int, Mat6>& step_covariance) {
  if (gt.size() != est.size())
    throw std::invalid_argument("camera metrics: " + std::to_string(est.size()) + " estimated poses for " +
                                std::to_string(gt.size()) + " ground-truth poses");
  CameraMetricsAccumulator acc;
  for (size_t k = 0; k < gt.size(); ++k) {
    const auto it = step_covariance.find(static_cast<int>(k));
    acc.add(gt[k], est[k], it == step_covariance.end() ? nullptr : &it->second);
  }
  return acc.result();
}

void RseAccumulator::add(const Vec3& est, const Vec3& gt) {
  sum_error_m_ += (est - gt).norm();
  sum_gt_m_ += gt.norm();
  ++pairs_;
}

std::optional<double> RseAccumulator::result() const {
  if (pairs_ == 0 || sum_gt_m_ <= 0.0) return std::nullopt;
  return 100.0 * sum_error_m_ / sum_gt_m_;
}

std::optional<double> ComputeRsePct(const std::vector<std::pair<Vec3, Vec3>>& pairs) {
  RseAccumulator acc;
  for (const auto& [est, gt] : pairs) acc.add(est, gt);
  return acc.result();
}

SE3 ObjectMotionError(const ObjectPairSample& s) {
  const SE3& L = s.L_world_object_gt_prev;
  const SE3 body_gt = L.inverse() * s.H_world_gt * L;
  const SE3 body_est = L.inverse() * s.H_world_est * L;
  return body_gt.inverse() * body_est;
}

void ObjectMetricsAccumulator::add(const ObjectPairSample& s) {
  addPair(s);
  if (s.estimated) addEstimate(s);
}

void ObjectMetricsAccumulator::addPair(const ObjectPairSample& pair) {
  ++counts_.gt_pairs;
  if (!pair.gtMoving()) return;
  ++counts_.gt_moving_pairs;
  if (pair.measurable) counts_.measurable_moving_pairs = counts_.measurable_moving_pairs.value_or(0) + *pair.measurable;
}

void ObjectMetricsAccumulator::addEstimate(const ObjectPairSample& s) {
  ++counts_.estimated_pairs;
  if (!s.gtMoving()) {
    ++counts_.static_pairs_estimated;
    sum_static_speed_ += s.speed_est_mps;
    false_dynamic_ += s.est_dynamic;
    return;
  }
  ++counts_.moving_pairs_estimated;
  measurable_moving_estimated_ += s.measurable.value_or(false);
  if (const std::optional<double> nees = MotionNees(s)) sum_nees_ += *nees, ++nees_pairs_;
  const SE3 e = ObjectMotionError(s);
  const SE3& L = s.L_world_object_gt_prev;
  sum_e_t_ += e.translation().norm();
  sum_e_r_deg_ += e.angle() * kRadToDeg;
  sum_gt_t_ += (L.inverse() * s.H_world_gt * L).translation().norm();
  sum_speed_err_ += std::abs(s.speed_est_mps - s.speed_gt_mps);
  sum_speed_gt_ += s.speed_gt_mps;
}

std::optional<double> MotionNees(const ObjectPairSample& s) {
  if (!s.estimated) return std::nullopt;
  // H about the anchor c: (R, t + R c - c); its tangent error: translation difference, rotation on the right.
  const Vec3& c = s.anchor_est;
  const Vec3 t_gt = s.H_world_gt.translation() + s.H_world_gt.rotation() * c - c;
  const Vec3 t_est = s.H_world_est.translation() + s.H_world_est.rotation() * c - c;
  Vec6 e;
  e << t_est - t_gt, RotationLog(s.H_world_gt.rotation().conjugate() * s.H_world_est.rotation());
  return NormalisedSquare(e, s.covariance_est);
}

ObjectMetrics ObjectMetricsAccumulator::result() const {
  ObjectMetrics m = counts_;
  if (m.gt_moving_pairs > 0) m.object_coverage = static_cast<double>(m.moving_pairs_estimated) / m.gt_moving_pairs;
  if (m.measurable_moving_pairs.value_or(0) > 0)
    m.object_coverage_measurable = static_cast<double>(measurable_moving_estimated_) / *m.measurable_moving_pairs;
  if (m.moving_pairs_estimated > 0) {
    const double n = m.moving_pairs_estimated;
    if (sum_gt_t_ > 0.0) {
      m.omte_pct = 100.0 * sum_e_t_ / sum_gt_t_;
      m.omre_deg_per_m = sum_e_r_deg_ / sum_gt_t_;
    }
    if (sum_speed_gt_ > 0.0) m.omse_pct = 100.0 * sum_speed_err_ / sum_speed_gt_;
    m.me_t_m = sum_e_t_ / n;
    m.me_r_deg = sum_e_r_deg_ / n;
    m.speed_err_mps = sum_speed_err_ / n;
  }
  if (nees_pairs_ > 0) m.motion_nees = sum_nees_ / nees_pairs_;
  if (m.static_pairs_estimated > 0) {
    m.static_mean_speed_mps = sum_static_speed_ / m.static_pairs_estimated;
    m.static_false_dynamic_frac = static_cast<double>(false_dynamic_) / m.static_pairs_estimated;
  }
  return m;
}

ObjectMetrics ComputeObjectMetrics(const std::vector<ObjectPairSample>& samples) {
  ObjectMetricsAccumulator acc;
  for (const auto& s : samples) acc.add(s);
  return acc.result();
}

}  // namespace dslam
