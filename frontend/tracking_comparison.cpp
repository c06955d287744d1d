#include "frontend/tracking_comparison.h"

#include <cmath>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

#include "data/dense_maps.h"

namespace dslam {

TrackingComparison::TrackingComparison(const std::vector<FlowMethod>& trackers, int max_corners)
    : methods_(trackers), max_corners_(max_corners), sums_(trackers.size() + 1) {}

void TrackingComparison::add(const ImageFrame& frame_k, const ImageFrame& frame_next) {
  const cv::Mat gray_k = GreyImage(frame_k.image), gray_next = GreyImage(frame_next.image);
  const cv::Mat& ids_k = frame_k.instance_ids;
  const cv::Mat& exact_flow = frame_k.flow_to_next;
  if (exact_flow.type() != CV_32FC2 || exact_flow.size() != gray_k.size())
    throw std::invalid_argument("tracking comparison: the exact flow must be CV_32FC2 of the image size");
  // Corners where the exact correspondence is known: the others cannot be scored.
  cv::Mat known = cv::Mat::zeros(gray_k.size(), CV_8U);
  for (int v = 0; v < known.rows; ++v)
    for (int u = 0; u < known.cols; ++u) {
      const cv::Vec2f f = exact_flow.at<cv::Vec2f>(v, u);
      known.at<uint8_t>(v, u) = std::abs(f[0]) < kUnknownFlow && std::abs(f[1]) < kUnknownFlow ? 255 : 0;
    }
  std::vector<cv::Point2f> corners;
  cv::goodFeaturesToTrack(gray_k, corners, max_corners_, 0.01, 7, known);
  std::vector<cv::Point2f> truth(corners.size());
  std::vector<uint8_t> on_object(corners.size(), 0);
  for (size_t i = 0; i < corners.size(); ++i) {
    const int u = cvRound(corners[i].x), v = cvRound(corners[i].y);
    const cv::Vec2f f = exact_flow.at<cv::Vec2f>(v, u);
    truth[i] = corners[i] + cv::Point2f(f[0], f[1]);
    if (!ids_k.empty()) {
      cv::Mat id;
      ids_k(cv::Rect(u, v, 1, 1)).convertTo(id, CV_32S);
      on_object[i] = id.at<int32_t>(0, 0) > 0;
    }
  }
  auto score = [&](Sums* s, const std::vector<cv::Point2f>& tracked, const std::vector<uint8_t>& ok) {
    for (size_t i = 0; i < corners.size(); ++i) {
      if (!ok[i]) continue;
      const double epe = cv::norm(tracked[i] - truth[i]);
      s->matches += 1, s->object_matches += on_object[i], s->epe_sum += epe;
      if (epe < kGoodMatchEpePx) s->good += 1, s->good_epe_sum += epe;
    }
  };
  score(&sums_[0], truth, std::vector<uint8_t>(corners.size(), 1));
  for (size_t m = 0; m < methods_.size(); ++m) {
    FlowParams params;
    params.method = methods_[m];
    FlowTracker tracker(params);
    const FlowResult r = tracker.track(gray_k, gray_next, corners, exact_flow);
    score(&sums_[m + 1], r.points, r.ok);
  }
  ++pairs_;
}

std::vector<TrackingScore> TrackingComparison::scores() const {
  std::vector<TrackingScore> out;
  for (size_t m = 0; m < sums_.size(); ++m) {
    const Sums& s = sums_[m];
    TrackingScore t;
    t.tracker = m == 0 ? "exact" : ToString(methods_[m - 1]);
    t.frame_pairs = pairs_;
    const double n = std::max(1, pairs_);
    t.matches = s.matches / n, t.object_matches = s.object_matches / n, t.good_matches = s.good / n;
    t.mean_epe_px = s.matches > 0 ? s.epe_sum / s.matches : 0.0;
    t.mean_good_epe_px = s.good > 0 ? s.good_epe_sum / s.good : 0.0;
    out.push_back(t);
  }
  return out;
}

}  // namespace dslam
