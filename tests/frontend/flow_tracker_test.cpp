#include "frontend/flow_tracker.h"

#include <gtest/gtest.h>

#include <iostream>

#include <opencv2/imgproc.hpp>

#include "support/synthetic_images.h"

namespace dslam {
namespace {

std::vector<cv::Point2f> Grid(int width, int height, int step, int margin) {
  std::vector<cv::Point2f> points;
  for (int v = margin; v < height - margin; v += step)
    for (int u = margin; u < width - margin; u += step) points.emplace_back(u, v);
  return points;
}

class FlowMethods : public ::testing::TestWithParam<FlowMethod> {};

TEST_P(FlowMethods, RecoverASubPixelTranslation) {
  const cv::Mat prev = test::RandomTexture(320, 200, 3);
  const double dx = 3.4, dy = -1.7;
  const cv::Mat curr = test::Shifted(prev, dx, dy);
  cv::Mat field(prev.size(), CV_32FC2, cv::Scalar(dx, dy));
  FlowParams params;
  params.method = GetParam();
  FlowTracker tracker(params);
  const auto points = Grid(prev.cols, prev.rows, 20, 30);
  const FlowResult r = tracker.track(prev, curr, points, field);
  // Both flows are sub-pixel (the bilinear shift of a blocky texture is not an exact translation locally).
  const double tolerance = GetParam() == FlowMethod::kLucasKanade ? 0.25 : GetParam() == FlowMethod::kDis ? 0.4 : 1e-4;
  int ok = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    if (!r.ok[i]) continue;
    ++ok;
    EXPECT_NEAR(r.points[i].x - points[i].x, dx, tolerance) << i;
    EXPECT_NEAR(r.points[i].y - points[i].y, dy, tolerance) << i;
  }
  EXPECT_GE(ok, static_cast<int>(0.9 * points.size()));
}

INSTANTIATE_TEST_SUITE_P(All, FlowMethods,
                         ::testing::Values(FlowMethod::kLucasKanade, FlowMethod::kDis, FlowMethod::kPrecomputed));

// Descriptor matching moves each point to a corner of the current image: on a shift, the matches it keeps
// land within a pixel or so of the truth (whole pixels, on a sub-pixel shift), and the points of a region
// whose content changed find few (random) matches.
TEST(FlowTracker, OrbMatchingFindsWholePixelShiftsAndNotChangedContent) {
  const cv::Mat prev = test::RandomTexture(320, 200, 7);
  cv::Mat curr = test::Shifted(prev, 5.0, -3.0);
  test::RandomTexture(160, 200, 98).copyTo(curr(cv::Rect(160, 0, 160, 200)));
  FlowParams params;
  params.method = ParseFlowMethod("orb");
  FlowTracker tracker(params);
  std::vector<cv::Point2f> corners;
  cv::goodFeaturesToTrack(prev, corners, 400, 0.01, 6);
  const FlowResult r = tracker.track(prev, curr, corners);
  int left = 0, left_ok = 0, left_exact = 0, right = 0, right_ok = 0;
  for (size_t i = 0; i < corners.size(); ++i) {
    const bool left_side = corners[i].x > 30 && corners[i].x < 130 && corners[i].y > 30 && corners[i].y < 170;
    if (left_side) {
      ++left, left_ok += r.ok[i];
      left_exact += r.ok[i] && cv::norm(r.points[i] - corners[i] - cv::Point2f(5.0f, -3.0f)) <= 1.5;
    }
    if (corners[i].x > 190) ++right, right_ok += r.ok[i];
  }
  ASSERT_GT(left, 20);
  EXPECT_GT(left_ok, 0.3 * left);
  EXPECT_GT(left_exact, 0.9 * left_ok);
  EXPECT_LT(right_ok, 0.2 * right);
  EXPECT_EQ(ToString(FlowMethod::kOrb), "orb");
}

TEST(FlowTracker, ForwardBackwardCheckRejectsPointsWhoseContentChanged) {
  const cv::Mat prev = test::RandomTexture(320, 200, 5);
  cv::Mat curr = test::Shifted(prev, 2.0, 0.0);
  // The right half is replaced by unrelated content (as if occluded): its points must not track.
  test::RandomTexture(160, 200, 99).copyTo(curr(cv::Rect(160, 0, 160, 200)));
  FlowTracker tracker(FlowParams{});
  const auto points = Grid(prev.cols, prev.rows, 16, 24);
  const FlowResult r = tracker.track(prev, curr, points);
  int left_ok = 0, left = 0, right_ok = 0, right = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    if (points[i].x < 130) ++left, left_ok += r.ok[i];
    if (points[i].x > 190) ++right, right_ok += r.ok[i];
  }
  EXPECT_GT(left_ok, 0.9 * left);
  EXPECT_LT(right_ok, 0.3 * right);  // a few random matches are consistent both ways
}

TEST(FlowTracker, PredictedPositionsLetLucasKanadeFollowALargeMotion) {
  const cv::Mat prev = test::RandomTexture(400, 200, 7);
  const double dx = 70.0;  // beyond what a 21 px window and 1 pyramid level find from the old position
  const cv::Mat curr = test::Shifted(prev, dx, 0.0);
  FlowParams params;
  params.lk_pyramid_levels = 1;
  FlowTracker tracker(params);
  std::vector<cv::Point2f> points, predicted;
  for (int v = 40; v < 160; v += 20)
    for (int u = 40; u < 300; u += 20) points.emplace_back(u, v), predicted.emplace_back(u + dx + 2.0f, v - 1.0f);
  const FlowResult with = tracker.track(prev, curr, points, cv::Mat(), predicted);
  const FlowResult without = tracker.track(prev, curr, points);
  int good_with = 0, good_without = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    good_with += with.ok[i] && std::abs(with.points[i].x - points[i].x - dx) < 0.3;
    good_without += without.ok[i] && std::abs(without.points[i].x - points[i].x - dx) < 0.3;
  }
  EXPECT_GT(good_with, 0.9 * points.size());
  EXPECT_LT(good_without, 0.2 * points.size());
}

TEST(FlowTracker, NearAPredictionItKeepsAPatchLeavingTheViewThatTheFullPyramidLoses) {
  // A textured car crosses a still background 105 px a frame and leaves the view at the right border of
  // a 640 px image: 160 px of it are in view, then 55 px, its rear. Started exactly where the points
  // go, the full pyramid (3 levels: a 120 px window at the coarsest) sees there mostly the still
  // background and the image border, and loses most of them; two levels keep them.
  const int width = 640, height = 240, car_length = 300, dx = 105, car_left = width - 160;
  const cv::Mat background = test::RandomTexture(width, height, 11);
  // The car's texture is fine-grained (2 px speckle, as a rendered car side): at the coarse levels it
  // averages out, and the background's blocks dominate the window.
  cv::Mat speckle(60, car_length / 2, CV_8UC1), car;
  cv::RNG rng(12);
  rng.fill(speckle, cv::RNG::UNIFORM, 40, 216);
  cv::resize(speckle, car, cv::Size(car_length, 120), 0, 0, cv::INTER_NEAREST);
  const auto frame = [&](int left) {
    cv::Mat image = background.clone();
    const cv::Rect seen = cv::Rect(left, 60, car_length, 120) & cv::Rect(0, 0, width, height);
    car(cv::Rect(seen.x - left, 0, seen.width, 120)).copyTo(image(seen));
    return image;
  };
  const cv::Mat prev = frame(car_left), curr = frame(car_left + dx);
  std::vector<cv::Point2f> points, predicted;
  for (int v = 72; v < 170; v += 6)
    for (int u = car_left + 6; u < width - dx - 6; u += 6) points.emplace_back(u, v), predicted.emplace_back(u + dx, v);
  FlowParams params;  // 15 px window, 3 levels
  FlowTracker tracker(params);
  const FlowResult full = tracker.track(prev, curr, points, cv::Mat(), predicted);
  const GreyPyramid prev_pyramid = BuildGreyPyramid(params, prev), curr_pyramid = BuildGreyPyramid(params, curr);
  const FlowResult near = tracker.trackNearPrediction(prev_pyramid, curr_pyramid, points, predicted);
  int full_good = 0, near_good = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    full_good += full.ok[i] && cv::norm(full.points[i] - predicted[i]) < 0.1;
    near_good += near.ok[i] && cv::norm(near.points[i] - predicted[i]) < 0.1;
  }
  std::cout << "full pyramid " << full_good << ", near the prediction " << near_good << " of " << points.size() << std::endl;
  EXPECT_GT(near_good, 0.9 * points.size());
  EXPECT_LT(full_good, 0.5 * points.size());
  // A prediction 4 px off is taken up.
  std::vector<cv::Point2f> off = predicted;
  for (auto& p : off) p += cv::Point2f(4.0f, -3.0f);
  const FlowResult near_off = tracker.trackNearPrediction(prev_pyramid, curr_pyramid, points, off);
  int off_good = 0;
  for (size_t i = 0; i < points.size(); ++i) off_good += near_off.ok[i] && cv::norm(near_off.points[i] - predicted[i]) < 0.1;
  EXPECT_GT(off_good, 0.9 * points.size());
  EXPECT_THROW(tracker.trackNearPrediction(prev_pyramid, curr_pyramid, points, {}), std::invalid_argument);
  FlowParams dis;
  dis.method = FlowMethod::kDis;
  FlowTracker dis_tracker(dis);
  EXPECT_TRUE(BuildGreyPyramid(dis, prev).levels.empty());  // only Lucas-Kanade reads a pyramid
  EXPECT_THROW(dis_tracker.trackNearPrediction(BuildGreyPyramid(dis, prev), BuildGreyPyramid(dis, curr), points, predicted),
               std::invalid_argument);
}

// A pyramid built once per frame and shared is only a saving: every search gives bit for bit what it gives
// on the bare images (which build their pyramids inside OpenCV), both ways, with and without predictions,
// at full depth and near a prediction.
TEST(FlowTracker, ASharedPyramidTracksExactlyAsTheBareImages) {
  const cv::Mat prev = test::RandomTexture(400, 240, 21);
  const cv::Mat curr = test::Shifted(prev, 6.3, -2.2);
  const auto points = Grid(prev.cols, prev.rows, 13, 4);  // some near the border, some that leave the view
  std::vector<cv::Point2f> predicted;
  for (const cv::Point2f& p : points) predicted.push_back(p + cv::Point2f(5.0f, -1.0f));
  FlowTracker tracker{FlowParams{}};
  const GreyPyramid prev_pyramid = BuildGreyPyramid(FlowParams{}, prev);
  const GreyPyramid curr_pyramid = BuildGreyPyramid(FlowParams{}, curr);
  ASSERT_EQ(prev_pyramid.levels.size(), 2u * (FlowParams{}.lk_pyramid_levels + 1));  // levels and derivatives
  const GreyPyramid bare_prev{prev, {}}, bare_curr{curr, {}};
  const auto expect_same = [&](const FlowResult& a, const FlowResult& b, const char* what) {
    ASSERT_EQ(a.points.size(), b.points.size()) << what;
    int tracked = 0;
    for (size_t i = 0; i < a.points.size(); ++i) {
      EXPECT_EQ(a.ok[i], b.ok[i]) << what << " point " << i;
      EXPECT_EQ(a.points[i], b.points[i]) << what << " point " << i;
      EXPECT_EQ(a.fb_error_px[i], b.fb_error_px[i]) << what << " point " << i;
      tracked += a.ok[i];
    }
    EXPECT_GT(tracked, static_cast<int>(points.size() / 2)) << what;
  };
  expect_same(tracker.track(prev_pyramid, curr_pyramid, points), tracker.track(prev, curr, points), "full");
  expect_same(tracker.track(prev_pyramid, curr_pyramid, points, cv::Mat(), predicted),
              tracker.track(bare_prev, bare_curr, points, cv::Mat(), predicted), "full, predicted");
  expect_same(tracker.trackNearPrediction(prev_pyramid, curr_pyramid, points, predicted),
              tracker.trackNearPrediction(bare_prev, bare_curr, points, predicted), "near the prediction");
}

TEST(FlowTracker, ExplainsWhatIsMissing) {
  FlowParams params;
  params.method = FlowMethod::kPrecomputed;
  FlowTracker tracker(params);
  const cv::Mat image = test::RandomTexture(64, 48, 1);
  EXPECT_THROW(tracker.track(image, image, {{10, 10}}), std::invalid_argument);  // no field
  EXPECT_THROW(tracker.track(image, image, {{10, 10}}, cv::Mat(10, 10, CV_32FC2)), std::invalid_argument);
  EXPECT_THROW(FlowTracker(FlowParams{}).track(image, cv::Mat(48, 64, CV_8UC3), {}), std::invalid_argument);
  EXPECT_THROW(ParseFlowMethod("farneback"), std::invalid_argument);
  EXPECT_EQ(ParseFlowMethod(ToString(FlowMethod::kDis)), FlowMethod::kDis);
  FlowParams bad;
  bad.fb_threshold_px = 0.0;
  EXPECT_THROW(FlowTracker{bad}, std::invalid_argument);
}

}  // namespace
}  // namespace dslam
