#include "evaluation/metrics.h"

#include <cmath>
#include <stdexcept>

namespace dslam {

CameraMetrics ComputeCameraMetrics(const std::vector<SE3>& gt, const std::vector<SE3>& est) {
  if (gt.size() != est.size())
    throw std::invalid_argument("camera metrics: " + std::to_string(est.size()) + " estimated poses for " +
                                std::to_string(gt.size()) + " ground-truth poses");
  CameraMetrics m;
  double sum_t = 0.0, sum_r_deg = 0.0, sum_sq_ate = 0.0;
  for (size_t k = 0; k < gt.size(); ++k) {
    sum_sq_ate += (gt[k].translation() - est[k].translation()).squaredNorm();
    if (k == 0) continue;
    const SE3 d_gt = gt[k - 1].inverse() * gt[k];
    const SE3 d_est = est[k - 1].inverse() * est[k];
    const SE3 e = d_gt.inverse() * d_est;
    m.path_length_m += d_gt.translation().norm();
    sum_t += e.translation().norm();
    sum_r_deg += e.angle() * kRadToDeg;
  }
  if (!gt.empty()) m.ate_m = std::sqrt(sum_sq_ate / static_cast<double>(gt.size()));
  const double steps = gt.size() > 1 ? static_cast<double>(gt.size() - 1) : 0.0;
  if (m.path_length_m >= kMinPathForRelativeErrorM) {
    m.rte_pct = 100.0 * sum_t / m.path_length_m;
    m.rre_deg_per_m = sum_r_deg / m.path_length_m;
  } else if (steps > 0) {
    m.mean_step_te_m = sum_t / steps;
    m.mean_step_re_deg = sum_r_deg / steps;
  }
  return m;
}

std::optional<double> ComputeRsePct(const std::vector<std::pair<Vec3, Vec3>>& pairs) {
  double num = 0.0, den = 0.0;
  for (const auto& [est, gt] : pairs) {
    num += (est - gt).norm();
    den += gt.norm();
  }
  if (pairs.empty() || den <= 0.0) return std::nullopt;
  return 100.0 * num / den;
}

SE3 ObjectMotionError(const ObjectPairSample& s) {
  const SE3& L = s.L_world_object_gt_prev;
  const SE3 body_gt = L.inverse() * s.H_world_gt * L;
  const SE3 body_est = L.inverse() * s.H_world_est * L;
  return body_gt.inverse() * body_est;
}

ObjectMetrics ComputeObjectMetrics(const std::vector<ObjectPairSample>& samples) {
  ObjectMetrics m;
  m.gt_pairs = static_cast<int>(samples.size());
  double sum_e_t = 0.0, sum_e_r_deg = 0.0, sum_gt_t = 0.0, sum_speed_err = 0.0, sum_speed_gt = 0.0;
  double sum_static_speed = 0.0;
  int false_dynamic = 0;
  for (const auto& s : samples) {
    if (!s.estimated) continue;
    ++m.estimated_pairs;
    if (!s.gtMoving()) {
      ++m.static_pairs_estimated;
      sum_static_speed += s.speed_est_mps;
      false_dynamic += s.est_dynamic;
      continue;
    }
    ++m.moving_pairs_estimated;
    const SE3 e = ObjectMotionError(s);
    const SE3& L = s.L_world_object_gt_prev;
    sum_e_t += e.translation().norm();
    sum_e_r_deg += e.angle() * kRadToDeg;
    sum_gt_t += (L.inverse() * s.H_world_gt * L).translation().norm();
    sum_speed_err += std::abs(s.speed_est_mps - s.speed_gt_mps);
    sum_speed_gt += s.speed_gt_mps;
  }
  if (m.gt_pairs > 0) m.object_coverage = static_cast<double>(m.estimated_pairs) / m.gt_pairs;
  if (m.moving_pairs_estimated > 0) {
    const double n = m.moving_pairs_estimated;
    if (sum_gt_t > 0.0) {
      m.omte_pct = 100.0 * sum_e_t / sum_gt_t;
      m.omre_deg_per_m = sum_e_r_deg / sum_gt_t;
    }
    if (sum_speed_gt > 0.0) m.omse_pct = 100.0 * sum_speed_err / sum_speed_gt;
    m.me_t_m = sum_e_t / n;
    m.me_r_deg = sum_e_r_deg / n;
    m.speed_err_mps = sum_speed_err / n;
  }
  if (m.static_pairs_estimated > 0) {
    m.static_mean_speed_mps = sum_static_speed / m.static_pairs_estimated;
    m.static_false_dynamic_frac = static_cast<double>(false_dynamic) / m.static_pairs_estimated;
  }
  return m;
}

}  // namespace dslam
