#include "lidar/scan_registration.h"

#include <cmath>
#include <stdexcept>

#include "lidar/pcl_module.h"

namespace dslam {

void ScanRegistrationParams::validate() const {
  if (!(voxel_m >= 0.0) || !std::isfinite(voxel_m)) throw std::invalid_argument("registration voxel_m must be >= 0");
  if (!(max_correspondence_m > 0.0) || !std::isfinite(max_correspondence_m))
    throw std::invalid_argument("registration max_correspondence_m must be positive");
  if (max_iterations < 1) throw std::invalid_argument("registration max_iterations must be >= 1");
  if (normal_neighbours < 3) throw std::invalid_argument("registration normal_neighbours must be >= 3");
  if (!(kept_pair_fraction > 0.0 && kept_pair_fraction <= 1.0))
    throw std::invalid_argument("registration kept_pair_fraction must be in (0, 1]");
  if (kept_pair_fraction < 1.0 && metric == RegistrationMetric::kGeneralized)
    throw std::invalid_argument("registration kept_pair_fraction below 1 needs point-to-plane or point-to-point ICP "
                                "(generalized ICP keeps every pair)");
}

Registration RegisterPoints(const std::vector<Eigen::Vector3f>& source, const std::vector<Eigen::Vector3f>& target,
                            const Eigen::Isometry3d& guess_target_source, const ScanRegistrationParams& params) {
  params.validate();
  return Pcl().register_points(source, target, guess_target_source, params);
}

}  // namespace dslam
