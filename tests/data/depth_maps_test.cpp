#include "data/depth_maps.h"

#include <algorithm>

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

}  // namespace
}  // namespace dslam
