#pragma once
// Relative camera motion between two frames from static points: PnP-RANSAC (OpenCV) on the previous
// frame's 3D points and their current pixels, with the information matrix of the inlier reprojections,
// and its fusion with an odometry increment when one is present (information-weighted, on the tangent
// space of the PnP estimate).

#include <optional>
#include <vector>

#include "data/measurements.h"
#include "geometry/pinhole_camera.h"

namespace dslam {

using Mat6 = Eigen::Matrix<double, 6, 6>;

struct PnpParams {
  double reprojection_px = 2.0;  // RANSAC inlier bound
  int iterations = 200;
  int min_inliers = 12;
  double pixel_sigma_px = 1.0;  // of a tracked feature, for the information matrix
  void validate() const;
};

struct PnpEstimate {
  SE3 T_prev_curr;
  Mat6 information = Mat6::Zero();  // of a right perturbation T_prev_curr * Exp(xi), xi = [rho; phi]
  std::vector<int> inliers;         // indices into the input
};

// How far the odometry increment is from the PnP motion given both uncertainties: the squared Mahalanobis
// distance, chi-square with 6 degrees of freedom when both are right (infinite when not finite).
double OdometryDisagreementChi2(const PnpEstimate& pnp, const OdometryMeasurement& odometry);

// nullopt with fewer than params.min_inliers consistent points. `guess` (T_prev_curr) seeds the solve.
std::optional<PnpEstimate> EstimateCameraMotionPnp(const std::vector<Vec3>& p_prev_camera, const std::vector<Vec2>& uv_curr,
                                                   const PinholeCamera& camera, const PnpParams& params,
                                                   const std::optional<SE3>& guess = std::nullopt);

// The information-weighted combination of the PnP estimate and an odometry increment.
SE3 FuseCameraMotion(const PnpEstimate& pnp, const OdometryMeasurement& odometry);

}  // namespace dslam
