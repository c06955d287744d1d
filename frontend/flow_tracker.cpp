#include "frontend/flow_tracker.h"

#include <cmath>
#include <stdexcept>

#include <opencv2/video/tracking.hpp>

namespace dslam {

std::string ToString(FlowMethod method) {
  switch (method) {
    case FlowMethod::kLucasKanade: return "lk";
    case FlowMethod::kDis: return "dis";
    case FlowMethod::kPrecomputed: return "precomputed";
  }
  return "?";
}

FlowMethod ParseFlowMethod(const std::string& name) {
  if (name == "lk") return FlowMethod::kLucasKanade;
  if (name == "dis") return FlowMethod::kDis;
  if (name == "precomputed") return FlowMethod::kPrecomputed;
  throw std::invalid_argument("unknown flow method '" + name + "' (expected lk, dis or precomputed)");
}

void FlowParams::validate() const {
  if (!(fb_threshold_px > 0.0)) throw std::invalid_argument("flow fb_threshold_px must be positive");
  if (lk_window_px < 5 || lk_window_px > 201) throw std::invalid_argument("frontend lk_window_px must be in 5..201");
  if (lk_pyramid_levels < 0 || lk_pyramid_levels > 8) throw std::invalid_argument("flow lk_pyramid_levels must be in 0..8");
}

struct FlowTracker::Dis {
  cv::Ptr<cv::DISOpticalFlow> flow = cv::DISOpticalFlow::create(cv::DISOpticalFlow::PRESET_FAST);
};

FlowTracker::FlowTracker(const FlowParams& params) : params_(params) {
  params_.validate();
  if (params_.method == FlowMethod::kDis) dis_ = std::make_unique<Dis>();
}

FlowTracker::~FlowTracker() = default;

namespace {

bool Inside(const cv::Point2f& p, const cv::Size& size) {
  return std::isfinite(p.x) && std::isfinite(p.y) && p.x >= 0.0f && p.y >= 0.0f && p.x <= size.width - 1.0f &&
         p.y <= size.height - 1.0f;
}

// Bilinear sample of a CV_32FC2 field at a sub-pixel position inside the image.
cv::Point2f SampleFlow(const cv::Mat& flow, const cv::Point2f& p) {
  const int x0 = std::min(static_cast<int>(p.x), flow.cols - 2), y0 = std::min(static_cast<int>(p.y), flow.rows - 2);
  const float ax = p.x - x0, ay = p.y - y0;
  const cv::Vec2f a = flow.at<cv::Vec2f>(y0, x0), b = flow.at<cv::Vec2f>(y0, x0 + 1);
  const cv::Vec2f c = flow.at<cv::Vec2f>(y0 + 1, x0), d = flow.at<cv::Vec2f>(y0 + 1, x0 + 1);
  const cv::Vec2f f = (1 - ay) * ((1 - ax) * a + ax * b) + ay * ((1 - ax) * c + ax * d);
  return {f[0], f[1]};
}

}  // namespace

FlowResult FlowTracker::track(const cv::Mat& prev_gray, const cv::Mat& curr_gray,
                              const std::vector<cv::Point2f>& prev_points, const cv::Mat& precomputed_flow,
                              const std::vector<cv::Point2f>& predicted) {
  if (prev_gray.type() != CV_8UC1 || curr_gray.type() != CV_8UC1 || prev_gray.size() != curr_gray.size())
    throw std::invalid_argument("flow needs two 8-bit grey images of one size");
  const cv::Size size = curr_gray.size();
  FlowResult result;
  result.points.resize(prev_points.size());
  result.ok.assign(prev_points.size(), 0);
  result.fb_error_px.assign(prev_points.size(), 0.0f);
  dense_forward_.release();

  if (params_.method == FlowMethod::kLucasKanade) {
    if (prev_points.empty()) return result;
    const cv::Size window(params_.lk_window_px, params_.lk_window_px);
    const cv::TermCriteria stop(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 30, 0.01);
    if (!predicted.empty() && predicted.size() != prev_points.size())
      throw std::invalid_argument("flow: one predicted position per point is needed");
    std::vector<uint8_t> status_fwd, status_bwd;
    std::vector<float> err;
    int flags = 0;
    if (!predicted.empty()) {
      result.points = predicted;
      flags = cv::OPTFLOW_USE_INITIAL_FLOW;
    }
    cv::calcOpticalFlowPyrLK(prev_gray, curr_gray, prev_points, result.points, status_fwd, err, window,
                             params_.lk_pyramid_levels, stop, flags);
    // The backward pass starts where the forward pass ended, moved back by the predicted motion (if any):
    // started at the origin it would return there even from a wrong match on an ambiguous texture.
    std::vector<cv::Point2f> back = result.points;
    if (!predicted.empty())
      for (size_t i = 0; i < back.size(); ++i) back[i] -= predicted[i] - prev_points[i];
    cv::calcOpticalFlowPyrLK(curr_gray, prev_gray, result.points, back, status_bwd, err, window,
                             params_.lk_pyramid_levels, stop, cv::OPTFLOW_USE_INITIAL_FLOW);
    for (size_t i = 0; i < prev_points.size(); ++i) {
      result.fb_error_px[i] = static_cast<float>(cv::norm(back[i] - prev_points[i]));
      result.ok[i] = status_fwd[i] && status_bwd[i] && Inside(result.points[i], size) &&
                     result.fb_error_px[i] <= params_.fb_threshold_px;
    }
    return result;
  }

  cv::Mat backward;
  if (params_.method == FlowMethod::kDis) {
    dis_->flow->calc(prev_gray, curr_gray, dense_forward_);
    dis_->flow->calc(curr_gray, prev_gray, backward);
  } else {
    if (precomputed_flow.empty())
      throw std::invalid_argument("flow method 'precomputed' needs a flow field for every frame but the last");
    if (precomputed_flow.type() != CV_32FC2 || precomputed_flow.size() != size)
      throw std::invalid_argument("precomputed flow must be CV_32FC2 of the image size (" + std::to_string(size.width) +
                                  "x" + std::to_string(size.height) + ")");
    dense_forward_ = precomputed_flow;
  }
  for (size_t i = 0; i < prev_points.size(); ++i) {
    if (!Inside(prev_points[i], size)) continue;
    result.points[i] = prev_points[i] + SampleFlow(dense_forward_, prev_points[i]);
    if (!Inside(result.points[i], size)) continue;
    if (!backward.empty()) {
      const cv::Point2f back = result.points[i] + SampleFlow(backward, result.points[i]);
      result.fb_error_px[i] = static_cast<float>(cv::norm(back - prev_points[i]));
      if (result.fb_error_px[i] > params_.fb_threshold_px) continue;
    }
    result.ok[i] = 1;
  }
  return result;
}

}  // namespace dslam
