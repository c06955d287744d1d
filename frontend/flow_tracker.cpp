#include "frontend/flow_tracker.h"

#include <cmath>
#include <stdexcept>

#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

namespace dslam {

std::string ToString(FlowMethod method) {
  switch (method) {
    case FlowMethod::kLucasKanade: return "lk";
    case FlowMethod::kDis: return "dis";
    case FlowMethod::kPrecomputed: return "precomputed";
    case FlowMethod::kOrb: return "orb";
  }
  return "?";
}

FlowMethod ParseFlowMethod(const std::string& name) {
  if (name == "lk") return FlowMethod::kLucasKanade;
  if (name == "dis") return FlowMethod::kDis;
  if (name == "precomputed") return FlowMethod::kPrecomputed;
  if (name == "orb") return FlowMethod::kOrb;
  throw std::invalid_argument("unknown flow method '" + name + "' (expected lk, dis, precomputed or orb)");
}

void FlowParams::validate() const {
  if (!(fb_threshold_px > 0.0)) throw std::invalid_argument("flow fb_threshold_px must be positive");
  if (lk_window_px < 5 || lk_window_px > 201) throw std::invalid_argument("frontend lk_window_px must be in 5..201");
  if (lk_pyramid_levels < 0 || lk_pyramid_levels > 8) throw std::invalid_argument("flow lk_pyramid_levels must be in 0..8");
}

struct FlowTracker::Dis {
  cv::Ptr<cv::DISOpticalFlow> flow = cv::DISOpticalFlow::create(cv::DISOpticalFlow::PRESET_FAST);
};

struct FlowTracker::Orb {
  // Upright descriptors (every angle 0): a road scene barely rotates in the image between frames.
  cv::Ptr<cv::ORB> orb = cv::ORB::create(500, 1.2f, 1, 31, 0, 2, cv::ORB::HARRIS_SCORE, 31);
  cv::BFMatcher matcher{cv::NORM_HAMMING};
};

FlowTracker::FlowTracker(const FlowParams& params) : params_(params) {
  params_.validate();
  if (params_.method == FlowMethod::kDis) dis_ = std::make_unique<Dis>();
  if (params_.method == FlowMethod::kOrb) orb_ = std::make_unique<Orb>();
}

FlowTracker::~FlowTracker() = default;

namespace {

// The deepest pyramid level of the search near a trusted prediction (OpenCV's maxLevel: 1 is two levels):
// enough to take up a prediction a few pixels off, too few for the coarse levels' windows (8 times the
// window at level 3) to reach past the image border or a nearby occluding edge, where they drag a point
// that moved far off its match.
constexpr int kNearPredictionLevels = 1;

void RequireGreyPair(const cv::Mat& prev_gray, const cv::Mat& curr_gray) {
  if (prev_gray.type() != CV_8UC1 || curr_gray.type() != CV_8UC1 || prev_gray.size() != curr_gray.size())
    throw std::invalid_argument("flow needs two 8-bit grey images of one size");
}

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

// What calcOpticalFlowPyrLK reads of an image: its pyramid where one was built, else the image.
cv::_InputArray LucasKanadeInput(const GreyPyramid& image) {
  return image.levels.empty() ? cv::_InputArray(image.gray) : cv::_InputArray(image.levels);
}

}  // namespace

GreyPyramid BuildGreyPyramid(const FlowParams& params, const cv::Mat& gray) {
  if (gray.type() != CV_8UC1) throw std::invalid_argument("flow needs 8-bit grey images");
  GreyPyramid out{gray, {}};
  if (params.method == FlowMethod::kLucasKanade)
    cv::buildOpticalFlowPyramid(gray, out.levels, cv::Size(params.lk_window_px, params.lk_window_px),
                                params.lk_pyramid_levels, true);
  return out;
}

FlowResult FlowTracker::LucasKanadeBothWays(const GreyPyramid& prev, const GreyPyramid& curr,
                                             const std::vector<cv::Point2f>& prev_points,
                                             const std::vector<cv::Point2f>& predicted, int levels) const {
  if (!predicted.empty() && predicted.size() != prev_points.size())
    throw std::invalid_argument("flow: one predicted position per point is needed");
  FlowResult result;
  result.points = predicted.empty() ? prev_points : predicted;
  result.ok.assign(prev_points.size(), 0);
  result.fb_error_px.assign(prev_points.size(), 0.0f);
  if (prev_points.empty()) return result;
  const cv::Size window(params_.lk_window_px, params_.lk_window_px);
  const cv::TermCriteria stop(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 30, 0.01);
  std::vector<uint8_t> status_fwd, status_bwd;
  std::vector<float> err;
  cv::calcOpticalFlowPyrLK(LucasKanadeInput(prev), LucasKanadeInput(curr), prev_points, result.points, status_fwd, err,
                           window, levels, stop,
                           predicted.empty() ? 0 : cv::OPTFLOW_USE_INITIAL_FLOW);
  // The backward pass starts where the forward pass ended, moved back by the predicted motion (if any):
  // started at the origin it would return there even from a wrong match on an ambiguous texture. Only the
  // points the forward pass kept inside the image go back (each point's search is independent of the others).
  std::vector<int> back_of;
  std::vector<cv::Point2f> from, back;
  back_of.reserve(prev_points.size());
  from.reserve(prev_points.size());
  back.reserve(prev_points.size());
  for (size_t i = 0; i < prev_points.size(); ++i) {
    if (!status_fwd[i] || !Inside(result.points[i], prev.gray.size())) continue;
    back_of.push_back(static_cast<int>(i));
    from.push_back(result.points[i]);
    back.push_back(predicted.empty() ? result.points[i] : result.points[i] - (predicted[i] - prev_points[i]));
  }
  if (from.empty()) return result;
  cv::calcOpticalFlowPyrLK(LucasKanadeInput(curr), LucasKanadeInput(prev), from, back, status_bwd, err, window,
                           levels, stop, cv::OPTFLOW_USE_INITIAL_FLOW);
  for (size_t j = 0; j < back_of.size(); ++j) {
    const int i = back_of[j];
    result.fb_error_px[i] = static_cast<float>(cv::norm(back[j] - prev_points[i]));
    result.ok[i] = status_bwd[j] && result.fb_error_px[i] <= params_.fb_threshold_px;
  }
  return result;
}

FlowResult FlowTracker::trackNearPrediction(const GreyPyramid& prev, const GreyPyramid& curr,
                                            const std::vector<cv::Point2f>& prev_points,
                                            const std::vector<cv::Point2f>& predicted) const {
  if (params_.method != FlowMethod::kLucasKanade) throw std::invalid_argument("flow: a search near a prediction is Lucas-Kanade's");
  RequireGreyPair(prev.gray, curr.gray);
  if (predicted.size() != prev_points.size())
    throw std::invalid_argument("flow: one predicted position per point is needed");
  return LucasKanadeBothWays(prev, curr, prev_points, predicted, std::min(kNearPredictionLevels, params_.lk_pyramid_levels));
}

FlowResult FlowTracker::track(const cv::Mat& prev_gray, const cv::Mat& curr_gray,
                              const std::vector<cv::Point2f>& prev_points, const cv::Mat& precomputed_flow,
                              const std::vector<cv::Point2f>& predicted) {
  return track(GreyPyramid{prev_gray, {}}, GreyPyramid{curr_gray, {}}, prev_points, precomputed_flow, predicted);
}

FlowResult FlowTracker::track(const GreyPyramid& prev, const GreyPyramid& curr,
                              const std::vector<cv::Point2f>& prev_points, const cv::Mat& precomputed_flow,
                              const std::vector<cv::Point2f>& predicted) {
  RequireGreyPair(prev.gray, curr.gray);
  dense_forward_.release();
  if (params_.method == FlowMethod::kOrb) return trackByDescriptors(prev.gray, curr.gray, prev_points);
  if (params_.method == FlowMethod::kLucasKanade)
    return LucasKanadeBothWays(prev, curr, prev_points, predicted, params_.lk_pyramid_levels);
  const cv::Mat& prev_gray = prev.gray;
  const cv::Mat& curr_gray = curr.gray;

  const cv::Size size = curr_gray.size();
  FlowResult result;
  result.points.resize(prev_points.size());
  result.ok.assign(prev_points.size(), 0);
  result.fb_error_px.assign(prev_points.size(), 0.0f);

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

FlowResult FlowTracker::trackByDescriptors(const cv::Mat& prev_gray, const cv::Mat& curr_gray,
                                           const std::vector<cv::Point2f>& prev_points) {
  FlowResult result;
  result.points = prev_points;
  result.ok.assign(prev_points.size(), 0);
  result.fb_error_px.assign(prev_points.size(), 0.0f);
  std::vector<cv::KeyPoint> prev_keys;
  for (size_t i = 0; i < prev_points.size(); ++i)
    if (Inside(prev_points[i], prev_gray.size()))
      prev_keys.emplace_back(prev_points[i], 31.0f, 0.0f, 0.0f, 0, static_cast<int>(i));
  // Candidates: Shi-Tomasi corners, the detector that made the points (a FAST corner sits a pixel or two off).
  std::vector<cv::Point2f> candidates;
  cv::goodFeaturesToTrack(curr_gray, candidates, 4 * std::max<int>(500, static_cast<int>(prev_points.size())), 0.005, 3);
  std::vector<cv::KeyPoint> curr_keys;
  for (const cv::Point2f& c : candidates) curr_keys.emplace_back(c, 31.0f, 0.0f, 0.0f, 0);
  cv::Mat prev_desc, curr_desc;
  // compute() drops the points too near the border to describe; class_id keeps each one's index.
  orb_->orb->compute(prev_gray, prev_keys, prev_desc);
  orb_->orb->compute(curr_gray, curr_keys, curr_desc);
  if (prev_keys.empty() || curr_keys.size() < 2) return result;
  std::vector<std::vector<cv::DMatch>> forward, backward;
  orb_->matcher.knnMatch(prev_desc, curr_desc, forward, 2);
  orb_->matcher.knnMatch(curr_desc, prev_desc, backward, 1);
  constexpr float kRatio = 0.8f;
  for (const auto& m : forward) {
    if (m.size() < 2 || m[0].distance >= kRatio * m[1].distance) continue;
    const auto& back = backward[static_cast<size_t>(m[0].trainIdx)];
    if (back.empty() || back[0].trainIdx != m[0].queryIdx) continue;  // not mutual
    const size_t i = static_cast<size_t>(prev_keys[static_cast<size_t>(m[0].queryIdx)].class_id);
    result.points[i] = curr_keys[static_cast<size_t>(m[0].trainIdx)].pt;
    result.ok[i] = 1;
  }
  return result;
}

}  // namespace dslam
