#include "frontend/feature_detector.h"

#include <algorithm>

#include <gtest/gtest.h>
#include <opencv2/features2d.hpp>

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

// The search skips the cells the existing points fill; what it finds is what a search of the whole image
// finds (FAST over the whole image, strongest first, equal responses in image order).
TEST(DetectOnGrid, SearchingOnlyTheOpenCellsFindsWhatTheWholeImageGives) {
  const cv::Mat gray = test::RandomTexture(320, 192, 5);
  FeatureGridParams params;
  params.cell_px = 24, params.per_cell = 2, params.fast_threshold = 12, params.min_distance_px = 5;
  cv::Mat allowed(gray.size(), CV_8UC1, cv::Scalar(255));
  allowed(cv::Rect(150, 60, 70, 50)).setTo(0);
  auto whole_image = [&](const std::vector<cv::Point2f>& existing) {
    std::vector<cv::KeyPoint> corners;
    cv::FastFeatureDetector::create(params.fast_threshold, true)->detect(gray, corners, allowed);
    std::sort(corners.begin(), corners.end(), [](const cv::KeyPoint& a, const cv::KeyPoint& b) {
      if (a.response != b.response) return a.response > b.response;
      return a.pt.y != b.pt.y ? a.pt.y < b.pt.y : a.pt.x < b.pt.x;
    });
    std::vector<cv::Point2f> taken = existing, out;
    for (const cv::KeyPoint& kp : corners) {
      const cv::Point cell(static_cast<int>(kp.pt.x) / 24, static_cast<int>(kp.pt.y) / 24);
      int in_cell = 0;
      bool near = false;
      for (const cv::Point2f& q : taken) {
        in_cell += cv::Point(static_cast<int>(q.x) / 24, static_cast<int>(q.y) / 24) == cell;
        near = near || cv::norm(kp.pt - q) < 5.0;
      }
      if (in_cell >= 2 || near) continue;
      taken.push_back(kp.pt);
      out.push_back(kp.pt);
    }
    return out;
  };
  EXPECT_EQ(DetectOnGrid(gray, allowed, {}, params), whole_image({}));
  // Most cells full already: a few open cells, here and there, searched alone.
  std::vector<cv::Point2f> existing;
  for (int y = 0; y < 192; y += 24)
    for (int x = 0; x < 320; x += 24)
      if ((x / 24 + 3 * (y / 24)) % 5 != 0) existing.insert(existing.end(), {{x + 4.0f, y + 4.0f}, {x + 16.0f, y + 16.0f}});
  const std::vector<cv::Point2f> found = DetectOnGrid(gray, allowed, existing, params);
  EXPECT_GT(found.size(), 10u);
  EXPECT_EQ(found, whole_image(existing));
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
