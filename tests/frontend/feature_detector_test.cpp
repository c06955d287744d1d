#include "frontend/feature_detector.h"

#include <gtest/gtest.h>

#include "support/synthetic_images.h"

namespace dslam {
namespace {

TEST(DetectOnGrid, SpreadsFeaturesOverCellsOnlyWhereAllowed) {
  const cv::Mat gray = test::RandomTexture(320, 192, 11);
  cv::Mat allowed(gray.size(), CV_8UC1, cv::Scalar(255));
  allowed(cv::Rect(100, 50, 80, 60)).setTo(0);  // e.g. an object's mask
  FeatureGridParams params;
  params.cell_px = 32, params.per_cell = 2, params.min_distance_px = 6;
  const auto points = DetectOnGrid(gray, allowed, {}, params);
  ASSERT_GT(points.size(), 80u);
  std::map<std::pair<int, int>, int> per_cell;
  for (const auto& p : points) {
    EXPECT_NE(allowed.at<uint8_t>(cvRound(p.y), cvRound(p.x)), 0) << p;
    ++per_cell[{static_cast<int>(p.x) / 32, static_cast<int>(p.y) / 32}];
  }
  for (const auto& [cell, n] : per_cell) EXPECT_LE(n, 2);
  EXPECT_GT(per_cell.size(), 45u);  // of 60 cells, minus the masked ones
  for (size_t i = 0; i < points.size(); ++i)
    for (size_t j = i + 1; j < points.size(); ++j) EXPECT_GE(cv::norm(points[i] - points[j]), 6.0);
}

TEST(DetectOnGrid, CountsExistingPointsTowardsTheirCells) {
  const cv::Mat gray = test::RandomTexture(128, 64, 2);
  FeatureGridParams params;
  params.cell_px = 64, params.per_cell = 1;
  const auto first = DetectOnGrid(gray, cv::Mat(), {}, params);
  EXPECT_EQ(first.size(), 2u);
  EXPECT_TRUE(DetectOnGrid(gray, cv::Mat(), first, params).empty());
}

TEST(SelectOnGrid, OneDetectionServesEveryThresholdAndRegion) {
  const cv::Mat gray = test::RandomTexture(320, 192, 5);
  FeatureGridParams strict;
  strict.cell_px = 24, strict.per_cell = 2, strict.fast_threshold = 20, strict.min_distance_px = 5;
  const std::vector<cv::KeyPoint> corners = DetectFastCorners(gray, 5);
  for (size_t i = 1; i < corners.size(); ++i) ASSERT_GE(corners[i - 1].response, corners[i].response);
  // A corner's response does not depend on the threshold: selecting at 20 from a detection at 5 is detecting at 20.
  const cv::Rect image(0, 0, gray.cols, gray.rows);
  EXPECT_EQ(SelectOnGrid(corners, image, cv::Mat(), {}, strict), DetectOnGrid(gray, cv::Mat(), {}, strict));
  // A region: its cells start at its corner, its mask is its size, the points come in image coordinates.
  const cv::Rect box(70, 40, 120, 96);
  cv::Mat inside(box.size(), CV_8UC1, cv::Scalar(255));
  inside(cv::Rect(0, 0, 60, 96)).setTo(0);  // only the right half
  FeatureGridParams dense = strict;
  dense.cell_px = 10, dense.per_cell = 1, dense.fast_threshold = 5;
  const std::vector<cv::Point2f> in_box = SelectOnGrid(corners, box, inside, {}, dense);
  ASSERT_GT(in_box.size(), 10u);
  for (const cv::Point2f& p : in_box) {
    EXPECT_TRUE(box.contains(cv::Point(static_cast<int>(p.x), static_cast<int>(p.y)))) << p;
    EXPECT_GE(p.x, box.x + 60.0f) << p;
  }
  // Existing points (image coordinates) fill their cells of the region.
  const std::vector<cv::Point2f> after = SelectOnGrid(corners, box, inside, in_box, dense);
  EXPECT_TRUE(after.empty()) << after.size();
  EXPECT_THROW(SelectOnGrid(corners, box, cv::Mat(gray.size(), CV_8UC1), {}, dense), std::invalid_argument);
}

TEST(SampleLattice, TakesEveryStepInsideTheMask) {
  cv::Mat allowed(40, 40, CV_8UC1, cv::Scalar(0));
  allowed(cv::Rect(10, 10, 20, 20)).setTo(1);
  const auto points = SampleLattice(allowed, cv::Rect(0, 0, 40, 40), 5);
  EXPECT_EQ(points.size(), 16u);
  for (const auto& p : points) EXPECT_TRUE(p.x >= 10 && p.x < 30 && p.y >= 10 && p.y < 30);
  EXPECT_THROW(SampleLattice(allowed, cv::Rect(0, 0, 40, 40), 0), std::invalid_argument);
}

}  // namespace
}  // namespace dslam
