#include "frontend/camera_motion.h"

#include <cmath>
#include <limits>
#include <stdexcept>

#include <Eigen/Cholesky>

#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

namespace dslam {

void PnpParams::validate() const {
  if (!(reprojection_px > 0.0)) throw std::invalid_argument("pnp reprojection_px must be positive");
  if (iterations < 1) throw std::invalid_argument("pnp iterations must be >= 1");
  if (min_inliers < 4) throw std::invalid_argument("pnp min_inliers must be >= 4");
  if (!(pixel_sigma_px > 0.0)) throw std::invalid_argument("pnp pixel_sigma_px must be positive");
}

namespace {

SE3 FromRvecTvec(const cv::Mat& rvec, const cv::Mat& tvec) {
  cv::Mat R_cv;
  cv::Rodrigues(rvec, R_cv);
  Mat3 R;
  Vec3 t;
  cv::cv2eigen(R_cv, R);
  cv::cv2eigen(tvec, t);
  return SE3(Eigen::Quaterniond(R).normalized(), t);
}

void ToRvecTvec(const SE3& T, cv::Mat* rvec, cv::Mat* tvec) {
  cv::Mat R_cv;
  cv::eigen2cv(Mat3(T.rotationMatrix()), R_cv);
  cv::Rodrigues(R_cv, *rvec);
  cv::eigen2cv(Vec3(T.translation()), *tvec);
}

}  // namespace

std::optional<PnpEstimate> EstimateCameraMotionPnp(const std::vector<Vec3>& p_prev_camera, const std::vector<Vec2>& uv_curr,
                                                   const PinholeCamera& camera, const PnpParams& params,
                                                   const std::optional<SE3>& guess) {
  params.validate();
  if (p_prev_camera.size() != uv_curr.size()) throw std::invalid_argument("PnP needs as many pixels as points");
  if (static_cast<int>(p_prev_camera.size()) < params.min_inliers) return std::nullopt;
  std::vector<cv::Point3f> object;
  std::vector<cv::Point2f> image;
  for (size_t i = 0; i < p_prev_camera.size(); ++i) {
    object.emplace_back(p_prev_camera[i].x(), p_prev_camera[i].y(), p_prev_camera[i].z());
    image.emplace_back(uv_curr[i].x(), uv_curr[i].y());
  }
  const cv::Matx33d K(camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0, 1);
  cv::Mat rvec, tvec;
  if (guess) ToRvecTvec(guess->inverse(), &rvec, &tvec);  // solvePnP wants T_curr_prev
  std::vector<int> inliers;
  const bool ok = cv::solvePnPRansac(object, image, K, cv::noArray(), rvec, tvec, guess.has_value(), params.iterations,
                                     static_cast<float>(params.reprojection_px), 0.999, inliers,
                                     guess ? cv::SOLVEPNP_ITERATIVE : cv::SOLVEPNP_EPNP);
  if (!ok || static_cast<int>(inliers.size()) < params.min_inliers) return std::nullopt;
  // Refine on the inliers (RANSAC's model comes from a minimal set), then re-select them.
  std::vector<cv::Point3f> object_in;
  std::vector<cv::Point2f> image_in;
  for (int i : inliers) object_in.push_back(object[i]), image_in.push_back(image[i]);
  cv::solvePnPRefineLM(object_in, image_in, K, cv::noArray(), rvec, tvec);
  const SE3 T_curr_prev = FromRvecTvec(rvec, tvec);

  PnpEstimate estimate;
  estimate.T_prev_curr = T_curr_prev.inverse();
  const double w = 1.0 / (params.pixel_sigma_px * params.pixel_sigma_px);
  const double bound2 = params.reprojection_px * params.reprojection_px;
  for (size_t i = 0; i < p_prev_camera.size(); ++i) {
    const Vec3 p = T_curr_prev * p_prev_camera[i];
    if (p.z() <= 0.0) continue;
    if ((camera.project(p) - uv_curr[i]).squaredNorm() > bound2) continue;
    estimate.inliers.push_back(static_cast<int>(i));
    // d(pixel)/d(xi) for T_curr_prev <- Exp(xi) T_curr_prev: [I, -[p]x] through the projection. Its
    // information equals that of the right perturbation of T_prev_curr (the same xi up to sign).
    Eigen::Matrix<double, 2, 3> J_proj;
    J_proj << camera.fx / p.z(), 0, -camera.fx * p.x() / (p.z() * p.z()), 0, camera.fy / p.z(),
        -camera.fy * p.y() / (p.z() * p.z());
    Eigen::Matrix<double, 3, 6> J_point;
    J_point << Mat3::Identity(), -Hat(p);
    const Eigen::Matrix<double, 2, 6> J = J_proj * J_point;
    estimate.information += w * J.transpose() * J;
  }
  if (static_cast<int>(estimate.inliers.size()) < params.min_inliers) return std::nullopt;
  return estimate;
}

double OdometryDisagreementChi2(const PnpEstimate& pnp, const OdometryMeasurement& odometry) {
  // Both as right perturbations of the PnP motion: delta ~ N(0, cov_pnp + cov_odometry) when both are right.
  const Mat6 cov_odometry = odometry.sigma.cwiseAbs2().asDiagonal();
  const Eigen::LDLT<Mat6> pnp_information(pnp.information);
  if (pnp_information.info() != Eigen::Success) return 0.0;
  const Mat6 cov = pnp_information.solve(Mat6::Identity()) + cov_odometry;
  const Vec6 delta = (pnp.T_prev_curr.inverse() * odometry.T_prev_curr).Log();
  const double chi2 = delta.dot(cov.ldlt().solve(delta));
  return std::isfinite(chi2) ? chi2 : std::numeric_limits<double>::infinity();
}

SE3 FuseCameraMotion(const PnpEstimate& pnp, const OdometryMeasurement& odometry) {
  const Mat6 information_odometry = odometry.sigma.cwiseInverse().cwiseAbs2().asDiagonal();
  const Vec6 delta = (pnp.T_prev_curr.inverse() * odometry.T_prev_curr).Log();
  const Vec6 step = (pnp.information + information_odometry).ldlt().solve(information_odometry * delta);
  return pnp.T_prev_curr * SE3::Exp(step);
}

}  // namespace dslam
