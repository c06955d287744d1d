#include "frontend/warped_patch_search.h"

#include <cmath>
#include <stdexcept>

#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

namespace dslam {
namespace {

// A neighbourhood stretched or squeezed more than this is not one the template can stand for.
constexpr double kMaxAreaChange = 16.0;
// A template flatter than this (grey-level standard deviation) correlates with anything.
constexpr double kMinTemplateStd = 3.0;
// The search reaches this share of the predicted move when that is more than its radius, up to this far.
constexpr double kRadiusPerMove = 1.0 / 3.0;
constexpr int kMaxRadiusPx = 64;
// The refinement's patch is this much larger than the template on each side, and may move the peak by
// at most this much.
constexpr int kRefineMarginPx = 8;
constexpr float kMaxRefinePx = 1.0f;

// Sub-pixel offset of a peak from its two neighbours along one axis (a parabola through the three).
float PeakOffset(float left, float centre, float right) {
  const float curvature = left - 2.f * centre + right;
  if (!(curvature < 0.f)) return 0.f;
  return std::max(-0.5f, std::min(0.5f, 0.5f * (left - right) / curvature));
}

// The (2 half + 1) px square patch whose pixel (x, y) shows the previous image at
// prev_px + A^-1 ((x, y) - (half, half)): the previous neighbourhood as the current frame would show it.
cv::Mat WarpedPatch(const cv::Mat& prev_gray, const cv::Point2f& prev_px, const cv::Matx22f& A_inv, int half) {
  const cv::Vec2f shift =
      cv::Vec2f(prev_px.x, prev_px.y) - A_inv * cv::Vec2f(static_cast<float>(half), static_cast<float>(half));
  const cv::Matx23f to_prev(A_inv(0, 0), A_inv(0, 1), shift[0], A_inv(1, 0), A_inv(1, 1), shift[1]);
  cv::Mat patch;
  cv::warpAffine(prev_gray, patch, to_prev, cv::Size(2 * half + 1, 2 * half + 1),
                 cv::INTER_LINEAR | cv::WARP_INVERSE_MAP, cv::BORDER_REPLICATE);
  return patch;
}

WarpedPatchMatch SearchOne(const cv::Mat& prev_gray, const cv::Mat& curr_gray, const WarpedPatchRequest& request,
                           const WarpedSearchParams& params) {
  const double det = request.A(0, 0) * request.A(1, 1) - request.A(0, 1) * request.A(1, 0);
  if (!std::isfinite(det) || std::abs(det) < 1.0 / kMaxAreaChange || std::abs(det) > kMaxAreaChange) return {};
  const cv::Matx22f A_inv = request.A.inv();
  const int h = params.half_patch_px, size = 2 * h + 1;
  // The template's footprint in the previous image must lie inside it.
  for (int sx : {-h, h})
    for (int sy : {-h, h}) {
      const cv::Vec2f d = A_inv * cv::Vec2f(static_cast<float>(sx), static_cast<float>(sy));
      const float u = request.prev_px.x + d[0], v = request.prev_px.y + d[1];
      if (!(u >= 0.f && v >= 0.f && u <= prev_gray.cols - 1.f && v <= prev_gray.rows - 1.f)) return {};
    }
  const cv::Mat patch = WarpedPatch(prev_gray, request.prev_px, A_inv, h);
  cv::Scalar mean, stddev;
  cv::meanStdDev(patch, mean, stddev);
  if (stddev[0] < kMinTemplateStd) return {};

  const int cu = static_cast<int>(std::lround(request.predicted_px.x));
  const int cv_ = static_cast<int>(std::lround(request.predicted_px.y));
  // A motion model some percent off puts a point that moves far that much farther off: the search
  // reaches a third of the predicted move when that is more than the radius (rendered 0005: a car
  // passing at 5 to 10 m, whose label slows by a fifth to a quarter for a frame, lands 40 to 50 px from
  // where its last motion puts it, 190 px away).
  const double move_px = cv::norm(request.predicted_px - request.prev_px);
  const int radius =
      std::max(params.radius_px, std::min(kMaxRadiusPx, static_cast<int>(std::ceil(kRadiusPerMove * move_px))));
  const int reach = radius + h;
  const cv::Rect area = cv::Rect(cu - reach, cv_ - reach, 2 * reach + 1, 2 * reach + 1) &
                        cv::Rect(0, 0, curr_gray.cols, curr_gray.rows);
  if (area.width < size + 2 || area.height < size + 2) return {};
  cv::Mat score;
  cv::matchTemplate(curr_gray(area), patch, score, cv::TM_CCOEFF_NORMED);
  cv::Point best;
  double best_score = 0.0;
  cv::minMaxLoc(score, nullptr, &best_score, nullptr, &best);
  // A peak on the edge of the searched area may be the slope of one outside it.
  if (best.x == 0 || best.y == 0 || best.x == score.cols - 1 || best.y == score.rows - 1) return {};
  if (!(best_score >= params.min_ncc)) return {};
  // The second-best peak: the best other local maximum. A magnified patch is smooth and its peak is
  // broad, so the scores next to the best are no rival; another maximum is.
  cv::Mat neighbourhood_max;
  cv::dilate(score, neighbourhood_max, cv::Mat());
  cv::Mat rivals = score >= neighbourhood_max;
  rivals.at<uint8_t>(best) = 0;
  double second_score = -1.0;
  cv::minMaxLoc(score, nullptr, &second_score, nullptr, nullptr, rivals);
  if (best_score - second_score < params.min_margin) return {};

  const float dx = PeakOffset(score.at<float>(best.y, best.x - 1), score.at<float>(best), score.at<float>(best.y, best.x + 1));
  const float dy = PeakOffset(score.at<float>(best.y - 1, best.x), score.at<float>(best), score.at<float>(best.y + 1, best.x));
  const cv::Point peak(area.x + best.x + h, area.y + best.y + h);

  // The correlation peak is good to a few tenths of a pixel; Lucas-Kanade between a larger warped
  // patch and the current image around the peak brings it to the flow's precision (the warp has taken
  // out what Lucas-Kanade cannot model). It must stay near the peak.
  const int H = h + kRefineMarginPx, big = 2 * H + 1;
  const cv::Rect around(peak.x - H, peak.y - H, big, big);
  if ((around & cv::Rect(0, 0, curr_gray.cols, curr_gray.rows)) != around) return {};
  cv::Mat big_patch = WarpedPatch(prev_gray, request.prev_px, A_inv, H);
  const cv::Point2f start(static_cast<float>(H) + dx, static_cast<float>(H) + dy);
  std::vector<cv::Point2f> from{cv::Point2f(static_cast<float>(H), static_cast<float>(H))}, to{start};
  std::vector<uint8_t> status;
  std::vector<float> error;
  cv::calcOpticalFlowPyrLK(big_patch, curr_gray(around), from, to, status, error, cv::Size(size, size), 0,
                           cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 20, 0.01),
                           cv::OPTFLOW_USE_INITIAL_FLOW);
  if (status.empty() || !status[0] || cv::norm(to[0] - start) > kMaxRefinePx) return {};
  const cv::Point2f px(static_cast<float>(around.x) + to[0].x, static_cast<float>(around.y) + to[0].y);

  // The template is small, and on a blocky texture a corner of two blocks looks like another such corner:
  // the larger patch, four times the area, must correlate as well at the refined position.
  cv::Mat seen, big_score;
  cv::getRectSubPix(curr_gray, cv::Size(big, big), px, seen, CV_32F);
  big_patch.convertTo(big_patch, CV_32F);
  cv::matchTemplate(seen, big_patch, big_score, cv::TM_CCOEFF_NORMED);
  if (!(big_score.at<float>(0, 0) >= params.min_ncc)) return {};

  WarpedPatchMatch match;
  match.ok = true;
  match.ncc = big_score.at<float>(0, 0);
  match.px = px;
  return match;
}

}  // namespace

void WarpedSearchParams::validate() const {
  if (radius_px < 0 || radius_px > 200) throw std::invalid_argument("frontend warped_search_radius_px must be in 0..200");
  if (half_patch_px < 2 || half_patch_px > 30) throw std::invalid_argument("warped search half patch must be in 2..30 px");
  if (!(min_ncc > 0.0 && min_ncc <= 1.0)) throw std::invalid_argument("frontend warped_search_min_ncc must be in (0, 1]");
  if (!(min_margin >= 0.0 && min_margin < 1.0)) throw std::invalid_argument("warped search margin must be in [0, 1)");
  if (!(min_deformation >= 0.0) || !std::isfinite(min_deformation))
    throw std::invalid_argument("frontend warped_search_min_deformation must be a finite number >= 0");
  if (!(max_flow_deformation >= min_deformation))
    throw std::invalid_argument("frontend warped_search_max_flow_deformation must be at least warped_search_min_deformation");
}

std::vector<WarpedPatchMatch> SearchWarpedPatches(const cv::Mat& prev_gray, const cv::Mat& curr_gray,
                                                  const std::vector<WarpedPatchRequest>& requests,
                                                  const WarpedSearchParams& params) {
  if (prev_gray.type() != CV_8UC1 || curr_gray.type() != CV_8UC1 || prev_gray.size() != curr_gray.size())
    throw std::invalid_argument("warped patch search needs two CV_8UC1 images of one size");
  params.validate();
  std::vector<WarpedPatchMatch> matches(requests.size());
  if (params.radius_px == 0) return matches;
  for (size_t i = 0; i < requests.size(); ++i) matches[i] = SearchOne(prev_gray, curr_gray, requests[i], params);
  return matches;
}

}  // namespace dslam
