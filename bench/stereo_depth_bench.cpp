// Stereo depth on a rendered pair (render-scene --stereo): SGBM's depth against the exact rendered depth,
// median |error| within 1 m of 5, 10, 20 and 30 m, and the share of pixels SGBM gives a depth to.
// Usage: bench_stereo_depth DATASET [FRAMES (default 20)]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <vector>

#include "data/image_dataset.h"

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: bench_stereo_depth DATASET [FRAMES]\n");
    return 2;
  }
  try {
    dslam::ImageDatasetOptions exact_options, stereo_options;
    stereo_options.depth_encoding = "stereo";
    const dslam::ImageDataset exact(argv[1], exact_options), stereo(argv[1], stereo_options);
    const int frames = std::min(exact.size(), argc > 2 ? std::atoi(argv[2]) : 20);
    const std::vector<double> ranges = {5.0, 10.0, 20.0, 30.0};
    std::vector<std::vector<double>> errors(ranges.size());
    long valid = 0, total = 0;
    for (int k = 0; k < frames; ++k) {
      const cv::Mat z = exact.read(k).depth_m, z_sgbm = stereo.read(k).depth_m;
      for (int v = 0; v < z.rows; ++v)
        for (int u = 0; u < z.cols; ++u) {
          const float zt = z.at<float>(v, u), zs = z_sgbm.at<float>(v, u);
          if (!(zt > 0.0f && zt < 40.0f)) continue;
          ++total;
          if (!(zs > 0.0f)) continue;
          ++valid;
          for (size_t r = 0; r < ranges.size(); ++r)
            if (std::abs(zt - ranges[r]) <= 1.0) errors[r].push_back(std::abs(zs - zt));
        }
    }
    std::printf("%s, %d frames: SGBM depth on %.1f %% of the pixels with exact depth under 40 m\n", argv[1], frames,
                100.0 * valid / std::max(1L, total));
    for (size_t r = 0; r < ranges.size(); ++r) {
      auto& e = errors[r];
      if (e.empty()) continue;
      std::nth_element(e.begin(), e.begin() + static_cast<std::ptrdiff_t>(e.size() / 2), e.end());
      std::printf("  at %4.0f m (+-1 m): median |SGBM - exact| %.3f m over %zu pixels\n", ranges[r], e[e.size() / 2],
                  e.size());
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_stereo_depth: %s\n", e.what());
    return 2;
  }
}
