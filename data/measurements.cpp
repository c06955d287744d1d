#include "data/measurements.h"

#include <cmath>
#include <set>
#include <sstream>

namespace dslam {

std::string FindInvalidMeasurement(const FrameMeasurement& frame) {
  std::ostringstream err;
  const std::string where = "frame " + std::to_string(frame.frame_index) + ": ";
  if (frame.odometry) {
    const auto& o = *frame.odometry;
    if (!o.T_prev_curr.translation().allFinite() || !o.T_prev_curr.rotation().coeffs().allFinite())
      return where + "odometry increment is not finite";
    if (!o.sigma.allFinite() || (o.sigma.array() <= 0.0).any())
      return where + "odometry sigmas must be positive and finite";
  }
  if (frame.camera_motion_guess && (!frame.camera_motion_guess->translation().allFinite() ||
                                    !frame.camera_motion_guess->rotation().coeffs().allFinite()))
    return where + "camera motion guess is not finite";
  for (const auto& p : frame.static_points)
    if (!p.p_camera.allFinite()) return where + "static point track " + std::to_string(p.track_id) + " is not finite";
  std::set<int> ids;
  for (const auto& obj : frame.objects) {
    if (!ids.insert(obj.object_id).second)
      return where + "object id " + std::to_string(obj.object_id) + " appears twice";
    if (!(obj.jitter_sigma_m >= 0.0 && std::isfinite(obj.jitter_sigma_m)))
      return where + "object " + std::to_string(obj.object_id) + " jitter sigma must be finite and >= 0";
    if (obj.mask_area_frac && !(*obj.mask_area_frac >= 0.0 && *obj.mask_area_frac <= 1.0))
      return where + "object " + std::to_string(obj.object_id) + " mask area share must be in [0, 1]";
    for (const auto& p : obj.points)
      if (!p.p_camera.allFinite())
        return where + "object " + std::to_string(obj.object_id) + " point track " + std::to_string(p.track_id) +
               " is not finite";
  }
  return {};
}

std::string FindInvalidMeasurement(const FrameMeasurement& frame, int expected_index) {
  if (frame.frame_index != expected_index)
    return "frame index " + std::to_string(frame.frame_index) + " out of sequence: expected " +
           std::to_string(expected_index);
  return FindInvalidMeasurement(frame);
}

ObjectMotionFit SummariseMotionFit(const SE3& H, const std::vector<Vec3>& src, const std::vector<Vec3>& dst,
                                   const std::vector<bool>& inlier) {
  ObjectMotionFit fit;
  fit.H_camera_prev = H;
  for (size_t i = 0; i < src.size(); ++i) {
    if (!inlier[i]) continue;
    fit.centroid_camera_prev += src[i];
    fit.residual_sq_sum_m2 += (dst[i] - H * src[i]).squaredNorm();
    ++fit.num_inliers;
  }
  if (fit.num_inliers > 0) fit.centroid_camera_prev /= static_cast<double>(fit.num_inliers);
  return fit;
}

}  // namespace dslam
