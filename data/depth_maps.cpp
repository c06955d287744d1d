#include "data/depth_maps.h"

#include "data/image_frame.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "data/stereo_wls.h"

namespace dslam {
namespace {

cv::Mat ToFloatSingleChannel(const cv::Mat& image, const char* what) {
  if (image.empty()) throw std::invalid_argument(std::string(what) + " is empty");
  if (image.channels() != 1)
    throw std::invalid_argument(std::string(what) + " must have one channel, has " + std::to_string(image.channels()));
  const int depth = image.depth();
  if (depth != CV_16U && depth != CV_16S && depth != CV_32F && depth != CV_64F && depth != CV_8U)
    throw std::invalid_argument(std::string(what) + " must be 8-bit, 16-bit or float");
  cv::Mat out;
  image.convertTo(out, CV_32F);
  return out;
}

// The matcher of the right image against the left: the same parameters over the mirrored range of
// disparities (negative: a right pixel's match lies to its right).
cv::Ptr<cv::StereoSGBM> RightMatcher(const cv::StereoSGBM& left) {
  return cv::StereoSGBM::create(-left.getMinDisparity() - left.getNumDisparities() + 1, left.getNumDisparities(),
                                left.getBlockSize(), left.getP1(), left.getP2(), left.getDisp12MaxDiff(),
                                left.getPreFilterCap(), left.getUniquenessRatio(), left.getSpeckleWindowSize(),
                                left.getSpeckleRange(), left.getMode());
}

cv::Mat Gray8(const cv::Mat& image, const char* what) {
  if (image.empty()) throw std::invalid_argument(std::string(what) + " image is empty");
  if (image.depth() != CV_8U) throw std::invalid_argument(std::string(what) + " image must be 8-bit");
  return GreyImage(image);
}

}  // namespace

cv::Mat DepthFromScaledImage(const cv::Mat& depth, double units_per_metre) {
  if (!(units_per_metre > 0.0)) throw std::invalid_argument("depth units per metre must be positive");
  if (depth.type() == CV_16UC1) {  // the common PNG case: scaled in the conversion, no NaN possible
    cv::Mat out;
    depth.convertTo(out, CV_32F, 1.0 / units_per_metre);
    return out;
  }
  cv::Mat out = ToFloatSingleChannel(depth, "depth image");
  out *= 1.0 / units_per_metre;
  cv::patchNaNs(out, 0.0);
  return out;
}

cv::Mat DepthFromDisparity(const cv::Mat& disparity, double units_per_pixel, double fx_times_baseline_m) {
  if (!(units_per_pixel > 0.0)) throw std::invalid_argument("disparity units per pixel must be positive");
  if (!(fx_times_baseline_m > 0.0)) throw std::invalid_argument("fx * baseline must be positive for disparity input");
  const cv::Mat d = ToFloatSingleChannel(disparity, "disparity image");
  cv::Mat out(d.size(), CV_32F, cv::Scalar(0));
  const float scale = static_cast<float>(units_per_pixel * fx_times_baseline_m);
  for (int v = 0; v < d.rows; ++v) {
    const float* in = d.ptr<float>(v);
    float* z = out.ptr<float>(v);
    for (int u = 0; u < d.cols; ++u)
      if (in[u] > 0.0f && std::isfinite(in[u])) z[u] = scale / in[u];
  }
  return out;
}

void StereoParams::validate() const {
  if (num_disparities <= 0 || num_disparities % 16 != 0)
    throw std::invalid_argument("stereo num_disparities must be a positive multiple of 16");
  if (block_size < 1 || block_size % 2 == 0) throw std::invalid_argument("stereo block_size must be odd and >= 1");
  if (uniqueness_ratio < 0) throw std::invalid_argument("stereo uniqueness_ratio must be >= 0");
  if (!(lr_max_difference_px >= 0.0 && lr_max_difference_px <= 64.0))
    throw std::invalid_argument("stereo lr_max_difference_px must be in [0, 64] (0: no check)");
  if (filter != "none" && filter != "wls")
    throw std::invalid_argument("unknown stereo filter '" + filter + "' (expected none or wls)");
  if (!(wls_lambda > 0.0 && wls_lambda <= 1e6)) throw std::invalid_argument("stereo wls_lambda must be in (0, 1e6]");
  if (!(wls_sigma_color > 0.0 && wls_sigma_color <= 100.0))
    throw std::invalid_argument("stereo wls_sigma_color must be in (0, 100]");
  if (!(wls_min_confidence >= 0.0 && wls_min_confidence <= 255.0))
    throw std::invalid_argument("stereo wls_min_confidence must be in [0, 255]");
}

cv::Mat DepthFromStereo(const cv::Mat& left, const cv::Mat& right, double fx, double baseline_m,
                        const StereoParams& params) {
  params.validate();
  const cv::Mat l = Gray8(left, "left"), r = Gray8(right, "right");
  if (l.size() != r.size())
    throw std::invalid_argument("stereo pair sizes differ: left " + std::to_string(l.cols) + "x" +
                                std::to_string(l.rows) + ", right " + std::to_string(r.cols) + "x" +
                                std::to_string(r.rows));
  // SGBM leaves its first num_disparities columns without a disparity (it searches only where the whole
  // range fits in the image): 10 % of a KITTI frame, where cars leave the view on the left. The pair is
  // matched with both images widened on the left by that range instead, and a left pixel keeps its
  // disparity only where its match lies in the right image proper (u - d >= 0); the widening is repeated
  // edge pixels, so that a match into it costs about what a match at the edge would and is then dropped.
  const int pad = params.num_disparities;
  cv::Mat l_wide, r_wide;
  cv::copyMakeBorder(l, l_wide, 0, 0, pad, 0, cv::BORDER_REPLICATE);
  cv::copyMakeBorder(r, r_wide, 0, 0, pad, 0, cv::BORDER_REPLICATE);
  const int p1 = 8 * params.block_size * params.block_size, p2 = 32 * params.block_size * params.block_size;
  cv::Ptr<cv::StereoSGBM> left_matcher = cv::StereoSGBM::create(0, params.num_disparities, params.block_size, p1, p2, 1,
                                                                63, params.uniqueness_ratio, 100, 2,
                                                                cv::StereoSGBM::MODE_SGBM_3WAY);
  cv::Mat disparity16;
  left_matcher->compute(l_wide, r_wide, disparity16);  // fixed point, 4 fractional bits; negative = invalid
  const bool lr_check = params.lr_max_difference_px > 0.0;
  if (lr_check || params.filter != "none") {
    // The right image's disparities (negative: its matches lie to the right), by the same matcher mirrored.
    const cv::Ptr<cv::StereoSGBM> right_matcher = RightMatcher(*left_matcher);
    cv::Mat right16;
    right_matcher->compute(r_wide, l_wide, right16);
    const int right_invalid16 = (right_matcher->getMinDisparity() - 1) * 16;
    if (params.filter == "wls") {
      cv::Mat filtered, confidence;  // confidence: CV_32F, 0..255; 0 where the left-right check failed
      Ximgproc().wls_filter(left_matcher, disparity16, l_wide, right16, params.wls_lambda, params.wls_sigma_color,
                            &filtered, &confidence);
      filtered.setTo(-1, confidence < params.wls_min_confidence);
      disparity16 = filtered;
    }
    if (lr_check) {
      // A left pixel u with disparity d matches right pixel u - d, whose own disparity must lead back to u.
      const int max_difference16 = static_cast<int>(std::lround(16.0 * params.lr_max_difference_px));
      for (int v = 0; v < disparity16.rows; ++v) {
        auto* dl = disparity16.ptr<int16_t>(v);
        const auto* dr = right16.ptr<int16_t>(v);
        for (int u = pad; u < disparity16.cols; ++u) {
          if (dl[u] <= 0) continue;
          const int ur = u - static_cast<int>(std::lround(dl[u] / 16.0));
          const int back16 = ur >= 0 && dr[ur] != right_invalid16 ? -static_cast<int>(dr[ur]) : -1;
          if (back16 <= 0 || std::abs(back16 - dl[u]) > max_difference16) dl[u] = -1;
        }
      }
    }
  }
  cv::Mat disparity_in_view = disparity16.colRange(pad, disparity16.cols).clone();
  for (int v = 0; v < disparity_in_view.rows; ++v) {
    auto* d = disparity_in_view.ptr<int16_t>(v);
    for (int u = 0; u < pad && u < disparity_in_view.cols; ++u)
      if (d[u] > 0 && 16 * u < d[u]) d[u] = -1;  // its match lies in the widening, outside the right image
  }
  return DepthFromDisparity(disparity_in_view, 16.0, fx * baseline_m);
}

cv::Mat DepthFromLidar(const std::vector<Eigen::Vector4f>& points_lidar, const Eigen::Matrix<double, 3, 4>& P_camera_lidar,
                       int width, int height, double min_depth_m) {
  if (width <= 0 || height <= 0) throw std::invalid_argument("LiDAR depth image size must be positive");
  cv::Mat depth(height, width, CV_32F, cv::Scalar(0));
  for (const Eigen::Vector4f& p : points_lidar) {
    const Eigen::Vector3d x = P_camera_lidar * Eigen::Vector4d(p.x(), p.y(), p.z(), 1.0);
    if (!(x.z() >= min_depth_m)) continue;  // also drops NaN
    const int u = static_cast<int>(std::lround(x.x() / x.z())), v = static_cast<int>(std::lround(x.y() / x.z()));
    if (u < 0 || u >= width || v < 0 || v >= height) continue;
    float& z = depth.at<float>(v, u);
    if (z == 0.0f || x.z() < z) z = static_cast<float>(x.z());
  }
  return depth;
}

cv::Mat DepthFromCameraPoints(const std::vector<Eigen::Vector3f>& points_camera, const PinholeCamera& camera,
                              double min_depth_m) {
  std::vector<Eigen::Vector4f> points;
  points.reserve(points_camera.size());
  for (const Eigen::Vector3f& p : points_camera) points.emplace_back(p.x(), p.y(), p.z(), 0.0f);
  Eigen::Matrix<double, 3, 4> K0 = Eigen::Matrix<double, 3, 4>::Zero();
  K0(0, 0) = camera.fx, K0(0, 2) = camera.cx, K0(1, 1) = camera.fy, K0(1, 2) = camera.cy, K0(2, 2) = 1.0;
  return DepthFromLidar(points, K0, camera.width, camera.height, min_depth_m);
}

cv::Mat FillSparseDepth(const cv::Mat& depth_m, int radius_px, const cv::Mat& labels, double max_background_spread) {
  if (depth_m.type() != CV_32FC1) throw std::invalid_argument("depth must be CV_32FC1 to fill");
  if (radius_px < 0) throw std::invalid_argument("fill radius must be >= 0");
  if (!(max_background_spread >= 0.0)) throw std::invalid_argument("background depth spread must be >= 0");
  const bool by_label = !labels.empty() && max_background_spread > 0.0;
  if (by_label && (labels.size() != depth_m.size() || (labels.type() != CV_16UC1 && labels.type() != CV_32SC1)))
    throw std::invalid_argument("labels to fill depth by must be CV_16UC1 or CV_32SC1 of the depth's size");
  // Erosion (minimum) over valid depths only: "none" becomes a huge finite sentinel first (OpenCV's
  // erosion pads the border with the type's maximum, which must not pass for a depth either). One buffer,
  // filled and read back in single passes: comparison masks and copies cost more than the erosion itself.
  constexpr float kNone = 1e30f;
  const cv::Mat window = cv::getStructuringElement(cv::MORPH_RECT, {2 * radius_px + 1, 2 * radius_px + 1});
  cv::Mat nearest(depth_m.size(), CV_32F), farthest;
  for (int v = 0; v < depth_m.rows; ++v) {
    const float* in = depth_m.ptr<float>(v);
    float* s = nearest.ptr<float>(v);
    for (int u = 0; u < depth_m.cols; ++u) s[u] = in[u] > 0.0f ? in[u] : kNone;
  }
  if (by_label) {
    // Dilation (maximum) over valid depths: "none" is 0, and the border pads with 0 too.
    cv::max(depth_m, 0.0f, farthest);
    cv::patchNaNs(farthest, 0.0);
    cv::dilate(farthest, farthest, window, {-1, -1}, 1, cv::BORDER_CONSTANT, cv::Scalar(0));
  }
  cv::erode(nearest, nearest, window);
  const float agree = static_cast<float>(1.0 + max_background_spread);
  for (int v = 0; v < depth_m.rows; ++v) {
    const float* in = depth_m.ptr<float>(v);
    float* out = nearest.ptr<float>(v);
    for (int u = 0; u < depth_m.cols; ++u)
      if (!(in[u] <= 0.0f) || !(out[u] < kNone / 2)) out[u] = in[u];
    if (!by_label) continue;
    const float* far = farthest.ptr<float>(v);
    const uint16_t* labels16 = labels.type() == CV_16UC1 ? labels.ptr<uint16_t>(v) : nullptr;
    const int* labels32 = labels16 ? nullptr : labels.ptr<int>(v);
    for (int u = 0; u < depth_m.cols; ++u) {
      if (!(in[u] <= 0.0f) || !(far[u] > out[u] * agree)) continue;  // its own return, or a window that agrees
      const bool background = labels16 ? labels16[u] == 0 : labels32[u] <= 0;
      if (background) out[u] = 0.0f;
    }
  }
  return nearest;
}

}  // namespace dslam
