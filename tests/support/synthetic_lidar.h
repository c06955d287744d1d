#pragma once
// A spinning LiDAR in a scene of boxes on flat ground, for tests of the LiDAR code: 64 scan lines from
// +2 to -24.8 degrees (a Velodyne HDL-64's span), rays cast in the camera frame (x right, y down, z
// forward), the nearest hit kept.

#include <cmath>
#include <limits>
#include <vector>

#include <Eigen/Core>

namespace dslam::test {

struct SceneBox {
  Eigen::Vector3f lo, hi;  // axis-aligned corners in the camera frame (y down: lo.y() is the top)
};

struct SyntheticLidar {
  Eigen::Vector3f origin = Eigen::Vector3f(0.0f, -0.08f, -0.27f);  // the LiDAR's centre, camera frame
  float ground_y = 1.65f;                                            // the ground plane y = ground_y
  float azimuth_half_deg = 60.0f, azimuth_step_deg = 0.2f;
  float max_range_m = 80.0f;

  std::vector<Eigen::Vector3f> scan(const std::vector<SceneBox>& boxes) const {
    std::vector<Eigen::Vector3f> points;
    for (int line = 0; line < 64; ++line) {
      const float elevation = (2.0f - line * 26.8f / 63.0f) * static_cast<float>(M_PI) / 180.0f;
      for (float az = -azimuth_half_deg; az <= azimuth_half_deg; az += azimuth_step_deg) {
        const float a = az * static_cast<float>(M_PI) / 180.0f;
        const Eigen::Vector3f dir(std::cos(elevation) * std::sin(a), -std::sin(elevation),
                                  std::cos(elevation) * std::cos(a));
        float best = max_range_m;
        if (dir.y() > 1e-6f) best = std::min(best, (ground_y - origin.y()) / dir.y());
        for (const SceneBox& b : boxes) {
          float t0 = 0.0f, t1 = std::numeric_limits<float>::max();
          bool hit = true;
          for (int i = 0; i < 3 && hit; ++i) {
            if (std::abs(dir[i]) < 1e-9f) {
              hit = origin[i] >= b.lo[i] && origin[i] <= b.hi[i];
              continue;
            }
            float ta = (b.lo[i] - origin[i]) / dir[i], tb = (b.hi[i] - origin[i]) / dir[i];
            if (ta > tb) std::swap(ta, tb);
            t0 = std::max(t0, ta), t1 = std::min(t1, tb);
            hit = t0 <= t1;
          }
          if (hit && t0 > 0.0f) best = std::min(best, t0);
        }
        if (best < max_range_m) points.push_back(origin + best * dir);
      }
    }
    return points;
  }
};

// A box standing on the ground: centre x and z, size along x, height, size along z.
inline SceneBox BoxOnGround(float x, float z, float size_x, float height, float size_z, float ground_y = 1.65f) {
  return {Eigen::Vector3f(x - size_x / 2, ground_y - height, z - size_z / 2), Eigen::Vector3f(x + size_x / 2, ground_y, z + size_z / 2)};
}

}  // namespace dslam::test
