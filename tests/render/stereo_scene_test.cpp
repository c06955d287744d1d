// render-scene --stereo --exact-flow: SGBM depth from the rendered pair against the exact depth (error
// against range), and the exact flow against what optical flow finds in the images.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <vector>


#include "data/image_dataset.h"
#include "frontend/tracking_comparison.h"
#include "support/rendered_city.h"

namespace dslam {
namespace {

double Median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

TEST(StereoScene, SgbmDepthOnTheRenderedPairIsCloseToTheExactDepthAndItsErrorGrowsWithRange) {
  const std::string dir = test::RenderedCity("stereo_city", 4, 1, true);
  ImageDatasetOptions exact_options, stereo_options;
  stereo_options.depth_encoding = "stereo";
  const ImageDataset exact(dir, exact_options), stereo(dir, stereo_options);
  ASSERT_NEAR(stereo.camera().fx, exact.camera().fx, 1e-9);
  // |SGBM - exact| per range bin (exact depth), over the pixels both have.
  const std::vector<double> edges = {4.0, 10.0, 20.0, 40.0};
  std::vector<std::vector<double>> errors(edges.size() - 1);
  int valid = 0, total = 0;
  for (int k = 0; k < exact.size(); ++k) {
    const cv::Mat z = exact.read(k).depth_m, z_sgbm = stereo.read(k).depth_m;
    for (int v = 0; v < z.rows; v += 2)
      for (int u = 0; u < z.cols; u += 2) {
        const float zt = z.at<float>(v, u), zs = z_sgbm.at<float>(v, u);
        if (!(zt > edges.front() && zt < edges.back())) continue;
        ++total;
        if (!(zs > 0.0f)) continue;
        ++valid;
        for (size_t b = 0; b + 1 < edges.size(); ++b)
          if (zt >= edges[b] && zt < edges[b + 1]) errors[b].push_back(std::abs(zs - zt));
      }
  }
  EXPECT_GT(valid, total / 2) << "SGBM gave depth to " << valid << " of " << total << " pixels";
  std::vector<double> medians;
  for (size_t b = 0; b + 1 < edges.size(); ++b) {
    ASSERT_GT(errors[b].size(), 500u) << "range bin " << b;
    medians.push_back(Median(errors[b]));
    std::cout << "median |SGBM - exact| at " << edges[b] << "-" << edges[b + 1] << " m: " << medians.back() << " m over "
              << errors[b].size() << " pixels\n";
    const double mid = 0.5 * (edges[b] + edges[b + 1]);
    // A quarter of a pixel of disparity at the bin's middle: dz = z^2 / (fx b) * 0.25.
    EXPECT_LT(medians.back(), mid * mid / (exact.camera().fx * 0.54) * 0.25 + 0.02) << "range " << mid << " m";
  }
  EXPECT_LT(medians.front(), medians.back());
}

TEST(StereoScene, TheExactFlowIsWhatOpticalFlowFindsAndItsOwnEndPointErrorIsZero) {
  const std::string dir = test::RenderedCity("stereo_city", 4, 1, true);
  ImageDatasetOptions options;
  const ImageDataset data(dir, options);
  ASSERT_TRUE(data.hasFlow());
  TrackingComparison comparison({FlowMethod::kPrecomputed, FlowMethod::kLucasKanade, FlowMethod::kOrb});
  ImageFrame previous = data.read(0);
  for (int k = 1; k < data.size(); ++k) {
    ImageFrame current = data.read(k);
    comparison.add(previous, current);
    previous = std::move(current);
  }
  const std::vector<TrackingScore> s = comparison.scores();
  ASSERT_EQ(s.size(), 4u);
  EXPECT_EQ(s[0].tracker, "exact");
  EXPECT_EQ(s[0].frame_pairs, data.size() - 1);
  EXPECT_GT(s[0].matches, 500.0);
  EXPECT_GT(s[0].object_matches, 50.0);
  EXPECT_EQ(s[0].mean_epe_px, 0.0);
  // The dataset's exact flow, tracked as a precomputed field, lands exactly on the correspondences.
  EXPECT_EQ(s[1].tracker, "precomputed");
  EXPECT_LT(s[1].mean_epe_px, 1e-4);
  // (A corner next to an unknown pixel samples it bilinearly and is dropped: a few per frame.)
  EXPECT_GT(s[1].matches, 0.99 * s[0].matches);
  // Lucas-Kanade on the images finds the same correspondences to a fraction of a pixel: the field is exact.
  EXPECT_EQ(s[2].tracker, "lk");
  EXPECT_GT(s[2].good_matches, 0.7 * s[0].matches);
  EXPECT_LT(s[2].mean_good_epe_px, 0.5);
  // Descriptor matching: fewer matches, whole pixels (the paper's finding: flow beats matching).
  EXPECT_EQ(s[3].tracker, "orb");
  EXPECT_LT(s[3].matches, s[2].matches);
  EXPECT_GT(s[3].good_matches, 0.0);
  EXPECT_GT(s[3].mean_good_epe_px, s[2].mean_good_epe_px);
}

}  // namespace
}  // namespace dslam
