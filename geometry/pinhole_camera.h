#pragma once
// A rectified pinhole camera (x right, y down, z forward; pixel centres at integer coordinates, as OpenCV).

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

}  // namespace dslam
