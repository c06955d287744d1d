#include "frontend/mask_box_prediction.h"

#include <gtest/gtest.h>

namespace dslam {
namespace {

constexpr int kImageWidth = 1242, kImageHeight = 375;

TEST(MaskBoxPrediction, ABoxInsideTheImageShiftsAndScales) {
  // A car coming closer: its box moves right by 10 px and grows by half.
  const cv::Rect before(100, 100, 40, 20), now(110, 95, 60, 30);
  const cv::Point2f corner = PredictFromMaskBoxes(before, now, {100, 100}, kImageWidth, kImageHeight);
  EXPECT_FLOAT_EQ(corner.x, 110.0f);
  EXPECT_FLOAT_EQ(corner.y, 95.0f);
  const cv::Point2f middle = PredictFromMaskBoxes(before, now, {120, 110}, kImageWidth, kImageHeight);
  EXPECT_FLOAT_EQ(middle.x, 140.0f);
  EXPECT_FLOAT_EQ(middle.y, 110.0f);
}

TEST(MaskBoxPrediction, ABoxCutByTheRightBorderIsAnchoredOnItsLeftEdgeAndLeavesTheView) {
  // A parked car passing out at the right: its box's left edge moves 25 px, its right edge is the
  // border. Squeezing the old box into the new one would keep every point inside; anchored on the left
  // edge (scale from the uncut height), a point near the border is predicted out of the view.
  const cv::Rect before(1000, 180, 242, 120), now(1025, 180, 217, 120);
  const cv::Point2f p = PredictFromMaskBoxes(before, now, {1230, 200}, kImageWidth, kImageHeight);
  EXPECT_FLOAT_EQ(p.x, 1255.0f);
  EXPECT_FLOAT_EQ(p.y, 200.0f);
  EXPECT_GT(p.x, kImageWidth - 1);
}

TEST(MaskBoxPrediction, ABoxCutByTheLeftBorderIsAnchoredOnItsRightEdge) {
  const cv::Rect before(0, 180, 97, 105), now(0, 180, 67, 105);  // leaving at the left, 30 px a frame
  const cv::Point2f p = PredictFromMaskBoxes(before, now, {20, 200}, kImageWidth, kImageHeight);
  EXPECT_FLOAT_EQ(p.x, -10.0f);
  EXPECT_FLOAT_EQ(p.y, 200.0f);
}

TEST(MaskBoxPrediction, TheScaleComesFromTheUncutAxis) {
  // Cut at the right, growing by 10 % in height: the horizontal offset from the left edge grows too.
  const cv::Rect before(1100, 100, 142, 100), now(1090, 95, 152, 110);
  const cv::Point2f p = PredictFromMaskBoxes(before, now, {1150, 150}, kImageWidth, kImageHeight);
  EXPECT_NEAR(p.x, 1090.0f + 50.0f * 1.1f, 1e-3);
  EXPECT_NEAR(p.y, 95.0f + 50.0f * 1.1f, 1e-3);
}

}  // namespace
}  // namespace dslam
