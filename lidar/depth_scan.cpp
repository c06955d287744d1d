#include "lidar/depth_scan.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace dslam {

void LidarBeamPattern::validate() const {
  if (beams < 2 || beams > 1024) throw std::invalid_argument("LiDAR beam pattern: beams must be in 2..1024");
  if (!(top_elevation_deg > bottom_elevation_deg) || top_elevation_deg >= 90.0 || bottom_elevation_deg <= -90.0)
    throw std::invalid_argument("LiDAR beam pattern: elevations must satisfy -90 < bottom < top < 90 degrees");
  if (!(azimuth_step_deg > 0.0 && azimuth_step_deg <= 10.0))
    throw std::invalid_argument("LiDAR beam pattern: azimuth step must be in (0, 10] degrees");
}

std::vector<Eigen::Vector3f> ScanFromDepth(const cv::Mat& depth_m, const PinholeCamera& camera,
                                           const LidarBeamPattern& pattern) {
  pattern.validate();
  if (depth_m.type() != CV_32FC1) throw std::invalid_argument("ScanFromDepth: depth must be CV_32FC1");
  if (depth_m.cols != camera.width || depth_m.rows != camera.height)
    throw std::invalid_argument("ScanFromDepth: depth is " + std::to_string(depth_m.cols) + "x" +
                                std::to_string(depth_m.rows) + " but the camera's images are " +
                                std::to_string(camera.width) + "x" + std::to_string(camera.height));
  const double deg = M_PI / 180.0;
  // The azimuths that fall in the image, with the camera's horizontal field of view.
  const double half_fov = std::max(std::atan2(camera.cx, camera.fx), std::atan2(camera.width - camera.cx, camera.fx));
  std::vector<Eigen::Vector3f> points;
  for (int b = 0; b < pattern.beams; ++b) {
    const double e = (pattern.top_elevation_deg -
                      b * (pattern.top_elevation_deg - pattern.bottom_elevation_deg) / (pattern.beams - 1)) * deg;
    for (double a = -half_fov; a <= half_fov; a += pattern.azimuth_step_deg * deg) {
      const Eigen::Vector3d d(std::cos(e) * std::sin(a), -std::sin(e), std::cos(e) * std::cos(a));
      const int u = static_cast<int>(std::lround(camera.fx * d.x() / d.z() + camera.cx));
      const int v = static_cast<int>(std::lround(camera.fy * d.y() / d.z() + camera.cy));
      if (u < 0 || u >= camera.width || v < 0 || v >= camera.height) continue;
      const float z = depth_m.at<float>(v, u);
      if (!(z > 0.0f) || !std::isfinite(z)) continue;
      points.push_back((d * (z / d.z())).cast<float>());
    }
  }
  return points;
}

}  // namespace dslam
