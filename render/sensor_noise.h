#pragma once
// Optional sensor noise on rendered frames: Gaussian noise on the colour, and on the depth with a
// standard deviation that grows with depth (sigma = sigma0 + k * z^2, as stereo and RGB-D sensors).
// Seeded per frame, deterministic. The ground truth files stay exact.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>

#include "render/rgbd_renderer.h"

namespace dslam {

struct SensorNoise {
  double image_sigma = 0.0;           // grey levels (0..255)
  double depth_sigma_m = 0.0;         // at zero depth
  double depth_sigma_per_m2 = 0.0;    // added per square metre of depth
  bool any() const { return image_sigma > 0.0 || depth_sigma_m > 0.0 || depth_sigma_per_m2 > 0.0; }
};

inline void AddSensorNoise(const SensorNoise& noise, uint64_t seed, RgbdFrame* frame) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n(0.0, 1.0);
  if (noise.image_sigma > 0.0)
    for (auto& c : frame->rgb) c = static_cast<uint8_t>(std::clamp(std::lround(c + noise.image_sigma * n(rng)), 0L, 255L));
  if (noise.depth_sigma_m > 0.0 || noise.depth_sigma_per_m2 > 0.0)
    for (auto& z : frame->depth_m) {
      if (z <= 0.0f) continue;  // no measurement stays no measurement
      const double sigma = noise.depth_sigma_m + noise.depth_sigma_per_m2 * z * z;
      z = static_cast<float>(std::max(0.01, z + sigma * n(rng)));
    }
}

}  // namespace dslam
