// Stereo depth on a rendered pair (render-scene --stereo) against the exact rendered depth, for each stereo
// setting: plain SGBM, SGBM with the left-right check, and with the WLS filter too. Prints the share of pixels
// (exact depth under 40 m) given a depth, the share of those off by more than 3 quarter pixels of disparity
// (mismatches), the same two shares in the image's left band as wide as the disparity range (where the right
// image sees only part of the scene), the median |error| within 1 m of 5, 10, 20 and 30 m, and the median time
// a pair.
// Usage: bench_stereo_depth DATASET [FRAMES (default 20)]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <vector>

#include "bench/percentile.h"
#include "data/frame_memory.h"
#include "data/image_dataset.h"

namespace {

struct Setting {
  const char* name;
  double lr_max_difference_px;
  const char* filter;
};

}  // namespace

int main(int argc, char** argv) {
  dslam::KeepFrameBuffersInHeap();  // as dslam runs (data/frame_memory.h)
  if (argc < 2) {
    std::fprintf(stderr, "usage: bench_stereo_depth DATASET [FRAMES]\n");
    return 2;
  }
  try {
    const dslam::ImageDataset exact(argv[1], dslam::ImageDatasetOptions{});
    const int frames = std::min(exact.size(), argc > 2 ? std::atoi(argv[2]) : 20);
    std::vector<cv::Mat> truth;
    for (int k = 0; k < frames; ++k) truth.push_back(exact.read(k).depth_m);
    const double fx_baseline = exact.camera().fx * 0.54;  // for the quarter-pixel bound only (KITTI's baseline)
    std::printf("%s, %d frames\n", argv[1], frames);
    const std::vector<double> ranges = {5.0, 10.0, 20.0, 30.0};
    for (const Setting& setting : {Setting{"sgbm", 0.0, "none"}, Setting{"sgbm + left-right check", 1.0, "none"},
                                   Setting{"sgbm + left-right check + wls", 1.0, "wls"}}) {
      dslam::ImageDatasetOptions options;
      options.depth_encoding = "stereo";
      options.stereo.lr_max_difference_px = setting.lr_max_difference_px;
      options.stereo.filter = setting.filter;
      const dslam::ImageDataset stereo(argv[1], options);
      std::vector<std::vector<double>> errors(ranges.size());
      std::vector<double> ms;
      long valid = 0, total = 0, mismatched = 0;
      long band_valid = 0, band_total = 0, band_mismatched = 0;  // u < num_disparities
      const int band_px = options.stereo.num_disparities;
      for (int k = 0; k < frames; ++k) {
        const auto start = std::chrono::steady_clock::now();
        const cv::Mat z_stereo = stereo.read(k).depth_m;
        ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
        const cv::Mat& z = truth[static_cast<size_t>(k)];
        for (int v = 0; v < z.rows; ++v)
          for (int u = 0; u < z.cols; ++u) {
            const float zt = z.at<float>(v, u), zs = z_stereo.at<float>(v, u);
            if (!(zt > 0.0f && zt < 40.0f)) continue;
            const bool in_band = u < band_px;
            ++total, band_total += in_band;
            if (!(zs > 0.0f)) continue;
            ++valid, band_valid += in_band;
            // 0.75 px of disparity at the true depth, in metres
            if (std::abs(zs - zt) > 0.75 * zt * zt / fx_baseline) ++mismatched, band_mismatched += in_band;
            for (size_t r = 0; r < ranges.size(); ++r)
              if (std::abs(zt - ranges[r]) <= 1.0) errors[r].push_back(std::abs(zs - zt));
          }
      }
      std::printf("%s: depth on %.1f %% of the pixels, %.2f %% of them off by > 0.75 px, %.0f ms a frame (read + match)\n",
                  setting.name, 100.0 * valid / std::max(1L, total), 100.0 * mismatched / std::max(1L, valid),
                  dslam::bench::Percentile(ms, 0.5));
      std::printf("  left band (u < %d px): depth on %.1f %% of its pixels, %.2f %% of them off by > 0.75 px\n", band_px,
                  100.0 * band_valid / std::max(1L, band_total), 100.0 * band_mismatched / std::max(1L, band_valid));
      for (size_t r = 0; r < ranges.size(); ++r) {
        auto& e = errors[r];
        if (e.empty()) continue;
        std::nth_element(e.begin(), e.begin() + static_cast<std::ptrdiff_t>(e.size() / 2), e.end());
        std::printf("  at %4.0f m (+-1 m): median |stereo - exact| %.3f m over %zu pixels\n", ranges[r],
                    e[e.size() / 2], e.size());
      }
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_stereo_depth: %s\n", e.what());
    return 2;
  }
}
