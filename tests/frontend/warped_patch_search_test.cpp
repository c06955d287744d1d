#include "frontend/warped_patch_search.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

#include "support/synthetic_images.h"

namespace dslam {
namespace {

// The current image is the previous one stretched by 60 % along u, sheared and moved: how the side of a
// car passing close by changes between two frames.
const cv::Matx22f kA(1.6f, 0.0f, 0.25f, 1.0f);
const cv::Point2f kCentre(200.f, 120.f), kShift(-30.f, 10.f);

cv::Point2f Mapped(const cv::Point2f& p) {
  const cv::Vec2f d = kA * cv::Vec2f(p.x - kCentre.x, p.y - kCentre.y);
  return kCentre + cv::Point2f(d[0], d[1]) + kShift;
}

cv::Mat Warped(const cv::Mat& prev) {
  const cv::Vec2f t = cv::Vec2f(kCentre.x + kShift.x, kCentre.y + kShift.y) - kA * cv::Vec2f(kCentre.x, kCentre.y);
  cv::Mat curr;
  cv::warpAffine(prev, curr, cv::Matx23f(kA(0, 0), kA(0, 1), t[0], kA(1, 0), kA(1, 1), t[1]), prev.size(),
                 cv::INTER_LINEAR, cv::BORDER_REFLECT);
  return curr;
}

std::vector<cv::Point2f> Points() {
  std::vector<cv::Point2f> points;
  for (float v = 80.f; v <= 160.f; v += 16.f)
    for (float u = 150.f; u <= 250.f; u += 16.f) points.emplace_back(u + 0.3f, v + 0.6f);
  return points;
}

TEST(WarpedPatchSearch, FindsPointsOnAStretchedAndShearedPatchThatTheFlowLoses) {
  const cv::Mat prev = test::RandomTexture(400, 240, 31);
  const cv::Mat curr = Warped(prev);
  const std::vector<cv::Point2f> points = Points();
  std::vector<WarpedPatchRequest> requests;
  std::vector<cv::Point2f> truth, predicted;
  for (const cv::Point2f& p : points) {
    truth.push_back(Mapped(p));
    predicted.push_back(truth.back() + cv::Point2f(7.f, -5.f));  // a motion model a little off
    requests.push_back({p, predicted.back(), kA});
  }
  const std::vector<WarpedPatchMatch> found = SearchWarpedPatches(prev, curr, requests, WarpedSearchParams{});
  ASSERT_EQ(found.size(), points.size());
  int good = 0;
  for (size_t i = 0; i < found.size(); ++i) {
    if (!found[i].ok) continue;
    EXPECT_LT(cv::norm(found[i].px - truth[i]), 0.15) << i;  // no wrong match, and the flow's precision
    EXPECT_GE(found[i].ncc, 0.85f);
    ++good;
  }
  EXPECT_GE(good, 0.8 * points.size());  // 39 to 42 of 42 over 40 textures

  // Lucas-Kanade from the same predicted start, as the front-end runs it, loses most of them.
  std::vector<cv::Point2f> lk = predicted;
  std::vector<uint8_t> status;
  std::vector<float> error;
  cv::calcOpticalFlowPyrLK(prev, curr, points, lk, status, error, cv::Size(15, 15), 3,
                           cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 30, 0.01),
                           cv::OPTFLOW_USE_INITIAL_FLOW);
  int lk_good = 0;
  for (size_t i = 0; i < points.size(); ++i) lk_good += status[i] && cv::norm(lk[i] - truth[i]) < 0.3;
  EXPECT_LT(lk_good, 0.5 * points.size());  // 0 to 6 of 42
}

TEST(WarpedPatchSearch, ReachesFartherFromThePredictionOfALargerMove) {
  // The same stretch and shear, moved 250 px: a motion model a fifth off misses by more than the radius,
  // and the search reaches a third of the move (up to 64 px).
  const cv::Mat prev = test::RandomTexture(900, 240, 34);
  const cv::Matx23f to_curr(kA(0, 0), kA(0, 1), 250.f - 200.f * (kA(0, 0) - 1.f), kA(1, 0), kA(1, 1), -kA(1, 0) * 200.f);
  cv::Mat curr;
  cv::warpAffine(prev, curr, to_curr, prev.size(), cv::INTER_LINEAR, cv::BORDER_REFLECT);
  WarpedSearchParams params;
  const cv::Point2f miss(60.f, 0.f);  // beyond the radius and a fifth of 250, within a third of it
  std::vector<WarpedPatchRequest> requests;
  std::vector<cv::Point2f> truth;
  for (const cv::Point2f& p : Points()) {
    const cv::Vec3f q(p.x, p.y, 1.f);
    truth.emplace_back(to_curr.row(0).dot(cv::Matx13f(q[0], q[1], q[2])), to_curr.row(1).dot(cv::Matx13f(q[0], q[1], q[2])));
    requests.push_back({p, truth.back() + miss, kA});
  }
  const std::vector<WarpedPatchMatch> found = SearchWarpedPatches(prev, curr, requests, params);
  int good = 0;
  for (size_t i = 0; i < found.size(); ++i) {
    if (!found[i].ok) continue;
    EXPECT_LT(cv::norm(found[i].px - truth[i]), 0.15) << i;
    ++good;
  }
  EXPECT_GE(good, 0.8 * requests.size());
}

TEST(WarpedPatchSearch, LeavesLostWhatItCannotTellApart) {
  const cv::Mat prev = test::RandomTexture(400, 240, 32);
  const cv::Mat curr = Warped(prev);
  const std::vector<cv::Point2f> points = Points();
  WarpedSearchParams params;

  // The true match beyond the search radius: nothing found, rather than a wrong match.
  std::vector<WarpedPatchRequest> far;
  for (const cv::Point2f& p : points) far.push_back({p, Mapped(p) + cv::Point2f(params.radius_px + 12.f, 0.f), kA});
  const auto far_found = SearchWarpedPatches(prev, curr, far, params);
  for (size_t i = 0; i < far.size(); ++i) EXPECT_FALSE(far_found[i].ok) << far_found[i].ncc << " at " << far_found[i].px << " truth " << Mapped(points[i]) << " pred " << far[i].predicted_px;

  // A texture that repeats every 12 px along u: every peak has a twin.
  cv::Mat tile = test::RandomTexture(12, 240, 33), periodic;
  cv::repeat(tile, 1, 34, periodic);
  const cv::Mat periodic_curr = Warped(periodic);
  std::vector<WarpedPatchRequest> repeated;
  for (const cv::Point2f& p : points) repeated.push_back({p, Mapped(p), kA});
  for (const WarpedPatchMatch& m : SearchWarpedPatches(periodic, periodic_curr, repeated, params)) EXPECT_FALSE(m.ok);

  // A flat patch matches anything; a neighbourhood squeezed to nothing is no patch at all.
  const cv::Mat flat(240, 400, CV_8UC1, cv::Scalar(128));
  EXPECT_FALSE(SearchWarpedPatches(flat, flat, {{{200.f, 120.f}, {200.f, 120.f}, cv::Matx22f::eye()}}, params)[0].ok);
  EXPECT_FALSE(
      SearchWarpedPatches(prev, curr, {{{200.f, 120.f}, Mapped({200.f, 120.f}), cv::Matx22f(0.01f, 0, 0, 1)}}, params)[0].ok);

  // The search off: nothing found.
  params.radius_px = 0;
  for (const WarpedPatchMatch& m : SearchWarpedPatches(prev, curr, repeated, params)) EXPECT_FALSE(m.ok);
}

TEST(WarpedPatchSearch, RefusesBadInputAndParameters) {
  const cv::Mat grey(50, 50, CV_8UC1, cv::Scalar(0)), colour(50, 50, CV_8UC3, cv::Scalar(0));
  EXPECT_THROW(SearchWarpedPatches(grey, colour, {}, WarpedSearchParams{}), std::invalid_argument);
  EXPECT_THROW(SearchWarpedPatches(grey, cv::Mat(40, 50, CV_8UC1), {}, WarpedSearchParams{}), std::invalid_argument);
  WarpedSearchParams p;
  p.min_ncc = 1.5;
  EXPECT_THROW(p.validate(), std::invalid_argument);
  p = {};
  p.radius_px = -1;
  EXPECT_THROW(p.validate(), std::invalid_argument);
  p = {};
  p.min_deformation = -0.1;
  EXPECT_THROW(p.validate(), std::invalid_argument);
  p = {};
  p.max_flow_deformation = 0.2;  // below min_deformation: no search would be asked for where it drops matches
  EXPECT_THROW(p.validate(), std::invalid_argument);
}

}  // namespace
}  // namespace dslam
