#include "data/depth_maps.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include <gtest/gtest.h>

#include "support/synthetic_images.h"

namespace dslam {
namespace {

TEST(DepthMaps, ScaledAndDisparityImagesGiveMetres) {
  cv::Mat mm(2, 2, CV_16UC1);
  mm.at<uint16_t>(0, 0) = 0, mm.at<uint16_t>(0, 1) = 1500, mm.at<uint16_t>(1, 0) = 65535, mm.at<uint16_t>(1, 1) = 1;
  const cv::Mat z = DepthFromScaledImage(mm, 1000.0);
  EXPECT_EQ(z.type(), CV_32FC1);
  EXPECT_FLOAT_EQ(z.at<float>(0, 0), 0.0f);
  EXPECT_FLOAT_EQ(z.at<float>(0, 1), 1.5f);
  EXPECT_FLOAT_EQ(z.at<float>(1, 0), 65.535f);

  cv::Mat disparity(1, 3, CV_16UC1);
  disparity.at<uint16_t>(0, 0) = 0, disparity.at<uint16_t>(0, 1) = 256 * 10, disparity.at<uint16_t>(0, 2) = 128;
  const cv::Mat zd = DepthFromDisparity(disparity, 256.0, 721.5 * 0.54);
  EXPECT_FLOAT_EQ(zd.at<float>(0, 0), 0.0f);
  EXPECT_NEAR(zd.at<float>(0, 1), 721.5 * 0.54 / 10.0, 1e-4);
  EXPECT_NEAR(zd.at<float>(0, 2), 721.5 * 0.54 / 0.5, 1e-3);
  EXPECT_THROW(DepthFromScaledImage(cv::Mat(2, 2, CV_8UC3), 1000.0), std::invalid_argument);
  EXPECT_THROW(DepthFromScaledImage(mm, 0.0), std::invalid_argument);
  EXPECT_THROW(DepthFromDisparity(disparity, 256.0, -1.0), std::invalid_argument);
}

TEST(DepthMaps, StereoMatchingRecoversAFrontoParallelPlane) {
  const cv::Mat right = test::RandomTexture(320, 160, 4);
  const double disparity = 12.0, fx = 700.0, baseline = 0.5;
  const cv::Mat left = test::Shifted(right, disparity, 0.0);  // a point at u in the right image is at u + d on the left
  const cv::Mat z = DepthFromStereo(left, right, fx, baseline);
  std::vector<float> valid;
  for (int v = 20; v < 140; ++v)
    for (int u = 160; u < 300; ++u)
      if (z.at<float>(v, u) > 0.0f) valid.push_back(z.at<float>(v, u));
  ASSERT_GT(valid.size(), 0.8 * 120 * 140);
  std::nth_element(valid.begin(), valid.begin() + valid.size() / 2, valid.end());
  EXPECT_NEAR(valid[valid.size() / 2], fx * baseline / disparity, 0.02 * fx * baseline / disparity);
  EXPECT_THROW(DepthFromStereo(left, right(cv::Rect(0, 0, 100, 100)), fx, baseline), std::invalid_argument);
}

// SGBM alone searches only where the whole disparity range fits in the image, so its first 128 columns
// never get a depth: 10 % of a KITTI frame, where cars leave the view. Widened on the left, they do, except
// the columns whose match lies left of the right image's edge.
TEST(DepthMaps, StereoGivesDepthInTheLeftBandWhereTheRightCameraSeesTheSameSurface) {
  const cv::Mat right = test::RandomTexture(320, 160, 4);
  const double disparity = 12.0, fx = 700.0, baseline = 0.5;
  const cv::Mat left = test::Shifted(right, disparity, 0.0);
  const StereoParams params;  // 128 disparities
  const cv::Mat z = DepthFromStereo(left, right, fx, baseline, params);
  int band = 0, band_given = 0, band_wrong = 0, outside_given = 0;
  for (int v = 20; v < 140; ++v) {
    for (int u = 16; u < params.num_disparities; ++u, ++band) {
      const float zs = z.at<float>(v, u);
      if (!(zs > 0.0f)) continue;
      ++band_given;
      if (std::abs(fx * baseline / zs - disparity) > 1.0) ++band_wrong;
    }
    for (int u = 0; u < static_cast<int>(disparity) - 1; ++u) outside_given += z.at<float>(v, u) > 0.0f;
  }
  EXPECT_GT(band_given, 0.9 * band);
  EXPECT_LE(band_wrong, band / 100);
  // Columns whose match would lie outside the right image: (almost) none is given one.
  EXPECT_LE(outside_given, 120 * 11 / 20);
}

// A textured wall at disparity 8 px and a textured box in front of it at 30 px: the 22 px of wall just left
// of the box on the left image are hidden from the right camera, so no match there can be right.
struct OccludedPair {
  cv::Mat left, right;
  static constexpr double kWallDisparity = 8.0, kBoxDisparity = 30.0, kFx = 700.0, kBaseline = 0.5;
  static constexpr int kBoxU = 200, kBoxV = 40, kBoxW = 80, kBoxH = 80;
  OccludedPair() {
    right = test::RandomTexture(400, 160, 4);
    left = test::Shifted(right, kWallDisparity, 0.0);
    const cv::Mat box = test::RandomTexture(kBoxW, kBoxH, 9);
    box.copyTo(left(cv::Rect(kBoxU, kBoxV, kBoxW, kBoxH)));
    box.copyTo(right(cv::Rect(kBoxU - static_cast<int>(kBoxDisparity), kBoxV, kBoxW, kBoxH)));
  }
  static double Depth(double disparity) { return kFx * kBaseline / disparity; }
  // Pixels of the left image given a depth, and those off by more than 1 px of disparity, in a region.
  static std::pair<int, int> Count(const cv::Mat& z, const cv::Rect& region, double disparity) {
    int given = 0, wrong = 0;
    for (int v = region.y; v < region.y + region.height; ++v)
      for (int u = region.x; u < region.x + region.width; ++u) {
        const float zs = z.at<float>(v, u);
        if (!(zs > 0.0f)) continue;
        ++given;
        if (std::abs(kFx * kBaseline / zs - disparity) > 1.0) ++wrong;
      }
    return {given, wrong};
  }
};

// The wall band the box hides from the right camera has no right match. Matched on the pair widened on
// the left (DepthFromStereo), SGBM's own consistency test (disp12MaxDiff 1) already drops nearly all of it;
// unwidened, it gave more than 5 % of the band a wrong disparity. The explicit left-right check must keep
// that so and keep the box, which both cameras see.
TEST(DepthMaps, NoStereoSettingGivesADepthWhereTheRightCameraSeesNothing) {
  const OccludedPair pair;
  const cv::Rect hidden(OccludedPair::kBoxU - 22 + 3, OccludedPair::kBoxV + 5, 22 - 6, OccludedPair::kBoxH - 10);
  const cv::Rect box(OccludedPair::kBoxU + 5, OccludedPair::kBoxV + 5, OccludedPair::kBoxW - 10, OccludedPair::kBoxH - 10);
  StereoParams plain, checked;
  checked.lr_max_difference_px = 1.0;
  const cv::Mat z_plain = DepthFromStereo(pair.left, pair.right, OccludedPair::kFx, OccludedPair::kBaseline, plain);
  const cv::Mat z_checked = DepthFromStereo(pair.left, pair.right, OccludedPair::kFx, OccludedPair::kBaseline, checked);
  const auto [hidden_plain, hidden_plain_wrong] = OccludedPair::Count(z_plain, hidden, OccludedPair::kWallDisparity);
  const auto [hidden_checked, hidden_checked_wrong] = OccludedPair::Count(z_checked, hidden, OccludedPair::kWallDisparity);
  EXPECT_LE(hidden_plain_wrong, hidden.area() / 50);
  EXPECT_LE(hidden_checked_wrong, hidden.area() / 50);
  EXPECT_LE(hidden_checked, hidden_plain);
  for (const cv::Mat& z : {z_plain, z_checked}) {
    const auto [box_given, box_wrong] = OccludedPair::Count(z, box, OccludedPair::kBoxDisparity);
    EXPECT_GT(box_given, 0.9 * box.area());
    EXPECT_EQ(box_wrong, 0);
  }
}

TEST(DepthMaps, TheWlsFilterKeepsTheDepthOfSurfacesBothCamerasSee) {
  const OccludedPair pair;
  StereoParams wls;
  wls.filter = "wls";
  const cv::Mat z = DepthFromStereo(pair.left, pair.right, OccludedPair::kFx, OccludedPair::kBaseline, wls);
  const cv::Rect box(OccludedPair::kBoxU + 5, OccludedPair::kBoxV + 5, OccludedPair::kBoxW - 10, OccludedPair::kBoxH - 10);
  const cv::Rect wall(300, 20, 80, 120);
  const auto [box_given, box_wrong] = OccludedPair::Count(z, box, OccludedPair::kBoxDisparity);
  const auto [wall_given, wall_wrong] = OccludedPair::Count(z, wall, OccludedPair::kWallDisparity);
  EXPECT_GT(box_given, 0.8 * box.area());
  EXPECT_LE(box_wrong, box.area() / 50);
  EXPECT_GT(wall_given, 0.8 * wall.area());
  EXPECT_LE(wall_wrong, wall.area() / 50);
}

TEST(DepthMaps, StereoSettingsOutOfRangeAreRefusedByName) {
  const auto refused = [](StereoParams p, const std::string& name) {
    try {
      p.validate();
    } catch (const std::invalid_argument& e) {
      return std::string(e.what()).find(name) != std::string::npos;
    }
    return false;
  };
  StereoParams p;
  p.filter = "bilateral";
  EXPECT_TRUE(refused(p, "filter"));
  p = {};
  p.lr_max_difference_px = -1.0;
  EXPECT_TRUE(refused(p, "lr_max_difference_px"));
  p = {};
  p.wls_lambda = 0.0;
  EXPECT_TRUE(refused(p, "wls_lambda"));
  p = {};
  p.wls_min_confidence = 300.0;
  EXPECT_TRUE(refused(p, "wls_min_confidence"));
  EXPECT_NO_THROW(StereoParams{}.validate());
}

TEST(DepthMaps, LidarPointsLandOnTheirPixelsAndTheNearestWins) {
  Eigen::Matrix<double, 3, 4> P;
  P << 100, 0, 50, 0, 0, 100, 40, 0, 0, 0, 1, 0;  // camera = LiDAR frame, fx = 100, centre (50, 40)
  const std::vector<Eigen::Vector4f> points = {{1.0f, 0.0f, 10.0f, 0.5f},   // u = 60, v = 40
                                               {2.0f, 0.0f, 20.0f, 0.5f},   // the same pixel, farther
                                               {0.0f, 0.0f, -5.0f, 0.5f},   // behind
                                               {100.0f, 0.0f, 1.5f, 0.5f}}; // outside the image
  const cv::Mat z = DepthFromLidar(points, P, 100, 80);
  EXPECT_FLOAT_EQ(z.at<float>(40, 60), 10.0f);
  EXPECT_EQ(cv::countNonZero(z), 1);
  const cv::Mat filled = FillSparseDepth(z, 2);
  EXPECT_FLOAT_EQ(filled.at<float>(42, 62), 10.0f);
  EXPECT_FLOAT_EQ(filled.at<float>(43, 60), 0.0f);
  EXPECT_EQ(cv::countNonZero(filled), 25);
}

// The definition, pixel by pixel: an empty pixel takes the smallest valid depth in its box.
TEST(DepthMaps, FillingSparseDepthTakesTheNearestValidDepthInTheBox) {
  cv::RNG rng(7);
  cv::Mat z(60, 90, CV_32F, cv::Scalar(0));
  for (int i = 0; i < 300; ++i) z.at<float>(rng.uniform(0, z.rows), rng.uniform(0, z.cols)) = rng.uniform(1.0f, 50.0f);
  z.at<float>(0, 0) = -1.0f;  // invalid, never a source
  for (int radius : {0, 1, 3}) {
    const cv::Mat filled = FillSparseDepth(z, radius);
    for (int v = 0; v < z.rows; ++v)
      for (int u = 0; u < z.cols; ++u) {
        if (z.at<float>(v, u) > 0.0f) {
          ASSERT_EQ(filled.at<float>(v, u), z.at<float>(v, u)) << "a valid depth must stay as it is";
          continue;
        }
        float nearest = 0.0f;
        for (int y = std::max(0, v - radius); y <= std::min(z.rows - 1, v + radius); ++y)
          for (int x = std::max(0, u - radius); x <= std::min(z.cols - 1, u + radius); ++x) {
            const float d = z.at<float>(y, x);
            if (d > 0.0f && (nearest == 0.0f || d < nearest)) nearest = d;
          }
        if (nearest > 0.0f)
          ASSERT_EQ(filled.at<float>(v, u), nearest) << "pixel " << u << "," << v << " radius " << radius;
        else
          ASSERT_EQ(filled.at<float>(v, u), z.at<float>(v, u)) << "pixel " << u << "," << v << " radius " << radius;
      }
  }
}

// With labels: object pixels as without them; a background pixel only where its box's depths agree within
// the spread, pixel by pixel.
TEST(DepthMaps, ABackgroundPixelIsFilledOnlyWhereTheDepthsAroundItAgree) {
  cv::RNG rng(11);
  cv::Mat z(60, 90, CV_32F, cv::Scalar(0));
  for (int i = 0; i < 400; ++i) {
    const int u = rng.uniform(0, z.cols);
    // A near object on the left third (5-5.4 m) in front of a far wall (20-21 m).
    z.at<float>(rng.uniform(0, z.rows), u) = u < 30 ? rng.uniform(5.0f, 5.4f) : rng.uniform(20.0f, 21.0f);
  }
  cv::Mat labels(z.size(), CV_32S, cv::Scalar(0));
  labels.colRange(0, 30).setTo(4);
  const int radius = 3;
  const double spread = 0.1;
  const cv::Mat plain = FillSparseDepth(z, radius);
  cv::Mat labels16;
  labels.convertTo(labels16, CV_16U);
  for (const cv::Mat& l : {labels, labels16}) {
    const cv::Mat filled = FillSparseDepth(z, radius, l, spread);
    int cleared = 0;
    for (int v = 0; v < z.rows; ++v)
      for (int u = 0; u < z.cols; ++u) {
        float lo = 0.0f, hi = 0.0f;
        for (int y = std::max(0, v - radius); y <= std::min(z.rows - 1, v + radius); ++y)
          for (int x = std::max(0, u - radius); x <= std::min(z.cols - 1, u + radius); ++x) {
            const float d = z.at<float>(y, x);
            if (d > 0.0f) lo = lo == 0.0f ? d : std::min(lo, d), hi = std::max(hi, d);
          }
        const bool own = z.at<float>(v, u) > 0.0f, object = u < 30;
        if (own || object || !(hi > lo * (1.0 + spread))) {
          ASSERT_EQ(filled.at<float>(v, u), plain.at<float>(v, u)) << "pixel " << u << "," << v;
        } else {
          ASSERT_EQ(filled.at<float>(v, u), 0.0f) << "pixel " << u << "," << v << ": the box spans " << lo << "-" << hi;
          ++cleared;
        }
      }
    EXPECT_GT(cleared, 20) << "background pixels by the object's edge";
  }
  EXPECT_THROW(FillSparseDepth(z, radius, labels, -0.1), std::invalid_argument);
  EXPECT_THROW(FillSparseDepth(z, radius, cv::Mat(z.size(), CV_8U, cv::Scalar(0)), 0.1), std::invalid_argument);
  EXPECT_THROW(FillSparseDepth(z, radius, cv::Mat(10, 10, CV_32S, cv::Scalar(0)), 0.1), std::invalid_argument);
  // No spread: the labels change nothing.
  EXPECT_EQ(cv::countNonZero(FillSparseDepth(z, radius, labels, 0.0) != plain), 0);
}

}  // namespace
}  // namespace dslam
