#include "frontend/frontend_params.h"

#include <cmath>
#include <stdexcept>

namespace dslam {

void FrontendParams::validate() const {
  flow.validate();
  static_grid.validate();
  object_grid.validate();
  association.validate();
  pnp.validate();
  warped_search.validate();
  if (!(odometry_gate_chi2 > 0.0) || !std::isfinite(odometry_gate_chi2))
    throw std::invalid_argument("frontend odometry_gate_chi2 must be a positive finite number");
  if (!(object_max_acceleration_mps2 > 0.0)) throw std::invalid_argument("frontend object_max_acceleration_mps2 must be positive");
  if (!(frame_interval_s > 0.0)) throw std::invalid_argument("frontend frame interval must be positive");
  if (object_lattice_step_px < 1) throw std::invalid_argument("frontend object_lattice_step_px must be >= 1");
  if (max_points_per_object < 3) throw std::invalid_argument("frontend max_points_per_object must be >= 3");
  if (min_points_per_object < 3 || min_points_per_object > max_points_per_object)
    throw std::invalid_argument("frontend min_points_per_object must be in 3..max_points_per_object");
  if (!(static_min_depth_m > 0.0) || !(static_max_depth_m > static_min_depth_m))
    throw std::invalid_argument("frontend static depth range must satisfy 0 < min < max");
  if (!(object_max_distance_m > 0.0)) throw std::invalid_argument("frontend object_max_distance_m must be positive");
  if (!(min_mask_area_pct >= 0.0 && min_mask_area_pct < 100.0))
    throw std::invalid_argument("frontend min_mask_area_pct must be in [0, 100)");
  if (mask_border_px < 0) throw std::invalid_argument("frontend mask_border_px must be >= 0");
  if (object_ransac.max_iterations < 1 || !(object_ransac.inlier_threshold_m > 0.0) || object_ransac.min_inliers < 3)
    throw std::invalid_argument("frontend object_ransac needs iterations >= 1, a positive threshold, min_inliers >= 3");
}

}  // namespace dslam
