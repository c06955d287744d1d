#pragma once
// A rectified pinhole camera (x right, y down, z forward; pixel centres at integer coordinates, as OpenCV).

#include <string>

#include "geometry/se3.h"

namespace dslam {

struct PinholeCamera {
  double fx = 721.5377, fy = 721.5377, cx = 609.5593, cy = 172.854;  // KITTI's P2
  int width = 1242, height = 375;

  Vec2 project(const Vec3& p_camera) const {
    return Vec2(fx * p_camera.x() / p_camera.z() + cx, fy * p_camera.y() / p_camera.z() + cy);
  }
  Vec3 backProject(double u, double v, double depth_m) const {
    return Vec3((u - cx) / fx * depth_m, (v - cy) / fy * depth_m, depth_m);
  }
  bool inImage(const Vec3& p_camera) const {
    if (p_camera.z() <= 0.0) return false;
    const Vec2 uv = project(p_camera);
    return uv.x() >= 0.0 && uv.x() < width && uv.y() >= 0.0 && uv.y() < height;
  }
};

// Empty when a width x height image can come from a camera with these intrinsics: the principal point lies
// in the middle half of the image, as it does for real lenses; else what is wrong. An image size taken
// from a stream's first frame is checked with it, so that a stray frame cannot fix the wrong size.
inline std::string FindSizeMismatch(const PinholeCamera& intrinsics, int width, int height) {
  const bool fits = width > 0 && height > 0 && intrinsics.cx >= 0.25 * width && intrinsics.cx <= 0.75 * width &&
                    intrinsics.cy >= 0.25 * height && intrinsics.cy <= 0.75 * height;
  if (fits) return {};
  return "a " + std::to_string(width) + "x" + std::to_string(height) + " image does not fit the calibration: its principal point (" +
         std::to_string(intrinsics.cx) + ", " + std::to_string(intrinsics.cy) + ") must lie in the middle half of the image";
}

}  // namespace dslam
