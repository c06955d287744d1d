#include "frontend/mask_edges.h"

#include <random>

#include <gtest/gtest.h>

namespace dslam {
namespace {

// The definition, pixel by pixel: more than one label in the clipped (2b + 1)-square window.
cv::Mat NearMaskEdgeByDefinition(const cv::Mat& labels, int b) {
  cv::Mat out(labels.size(), CV_8UC1, cv::Scalar(0));
  if (b <= 0) return out;
  for (int v = 0; v < labels.rows; ++v)
    for (int u = 0; u < labels.cols; ++u) {
      const int32_t first = labels.at<int32_t>(v, u);
      bool mixed = false;
      for (int y = std::max(0, v - b); y <= std::min(labels.rows - 1, v + b) && !mixed; ++y)
        for (int x = std::max(0, u - b); x <= std::min(labels.cols - 1, u + b) && !mixed; ++x)
          mixed = labels.at<int32_t>(y, x) != first;
      out.at<uint8_t>(v, u) = mixed ? 255 : 0;
    }
  return out;
}

// Rectangles of random labels (some above 2^24, which a float image cannot tell apart) on background.
cv::Mat RandomBoxes(std::mt19937& rng, cv::Size size) {
  cv::Mat labels(size, CV_32SC1, cv::Scalar(0));
  std::uniform_int_distribution<int> x(-5, size.width), y(-5, size.height), side(1, 25), id(1, 6);
  for (int i = 0; i < 12; ++i) {
    const cv::Rect box = cv::Rect(x(rng), y(rng), side(rng), side(rng)) & cv::Rect({}, size);
    const int label = id(rng);
    labels(box).setTo(label > 4 ? (1 << 24) + label - 4 : label);
  }
  return labels;
}

TEST(NearMaskEdge, MarksEveryPixelWhoseWindowHoldsTwoLabelsAndNoOther) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 20; ++trial) {
    const cv::Mat labels = RandomBoxes(rng, cv::Size(61 + trial, 37));
    for (int b = 0; b <= 3; ++b) {
      const cv::Mat expected = NearMaskEdgeByDefinition(labels, b);
      const cv::Mat got = NearMaskEdge(labels, b);
      ASSERT_EQ(got.type(), CV_8UC1);
      ASSERT_EQ(cv::countNonZero(got != expected), 0) << "trial " << trial << ", border " << b;
      if (b > 0 && trial == 0) {
        EXPECT_GT(cv::countNonZero(got), 0);
      }
    }
  }
}

TEST(NearMaskEdge, OneLabelEverywhereHasNoEdgeAndOtherTypesAreRefused) {
  EXPECT_EQ(cv::countNonZero(NearMaskEdge(cv::Mat(20, 30, CV_32SC1, cv::Scalar(3)), 2)), 0);
  EXPECT_THROW(NearMaskEdge(cv::Mat(20, 30, CV_16UC1, cv::Scalar(3)), 2), std::invalid_argument);
}

}  // namespace
}  // namespace dslam
