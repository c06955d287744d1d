#pragma once
// Moves points from the previous image to the current one by optical flow, with a forward-backward
// consistency check: a point is kept only if flowing it back lands within `fb_threshold_px` of where
// it started. Three methods share the interface:
//  - sparse pyramidal Lucas-Kanade (OpenCV), forward and backward on the points only;
//  - dense DIS (OpenCV), forward and backward fields sampled at the points;
//  - a precomputed dense forward field (e.g. a dataset's .flo files); with no backward field the check
//    is skipped and every point that stays inside the image is kept;
//  - descriptor matching (the paper's alternative to flow): upright ORB descriptors at the points are
//    matched over the whole image to Shi-Tomasi corners of the current image, kept when the best match is
//    clearly better than the second (ratio 0.8) and mutual; the points land on whole pixels.

#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace dslam {

enum class FlowMethod { kLucasKanade, kDis, kPrecomputed, kOrb };
std::string ToString(FlowMethod method);
FlowMethod ParseFlowMethod(const std::string& name);  // "lk", "dis", "precomputed", "orb"; throws otherwise

struct FlowParams {
  FlowMethod method = FlowMethod::kLucasKanade;
  double fb_threshold_px = 1.0;
  int lk_window_px = 15;  // 21 tracks no better on KITTI-sized frames and costs twice as much
  int lk_pyramid_levels = 3;
  void validate() const;
};

// A grey image and, for Lucas-Kanade, its pyramid (levels and their derivatives, bordered as
// calcOpticalFlowPyrLK wants them), built once per frame by BuildGreyPyramid() and shared by every
// search from or to that frame: each Lucas-Kanade call on bare images builds both images' pyramids and
// the first one's derivatives again (a front-end frame made six such calls).
struct GreyPyramid {
  cv::Mat gray;                 // CV_8UC1
  std::vector<cv::Mat> levels;  // empty: a search builds what it needs from `gray`
};

// `gray` (CV_8UC1) with the pyramid a FlowTracker of these parameters searches (none for methods other than
// Lucas-Kanade). Depends on nothing else: any thread may build a frame's.
GreyPyramid BuildGreyPyramid(const FlowParams& params, const cv::Mat& gray);

struct FlowResult {
  std::vector<cv::Point2f> points;  // positions in the current image
  std::vector<uint8_t> ok;          // 1: tracked, inside the image and forward-backward consistent
  std::vector<float> fb_error_px;   // forward-backward distance (0 where the forward pass lost the point, or
                                    // without a backward field)
};

class FlowTracker {
 public:
  explicit FlowTracker(const FlowParams& params);
  ~FlowTracker();
  FlowTracker(const FlowTracker&) = delete;
  FlowTracker& operator=(const FlowTracker&) = delete;


  // prev_gray, curr_gray: CV_8UC1 of one size. precomputed_flow (CV_32FC2, prev -> curr) is used only by
  // the precomputed method, which throws std::invalid_argument without it. `predicted` (one per point, or
  // empty) starts Lucas-Kanade where a motion model expects each point: on a fast-moving, repetitive
  // texture the search from the old position can lock onto the wrong period.
  FlowResult track(const cv::Mat& prev_gray, const cv::Mat& curr_gray, const std::vector<cv::Point2f>& prev_points,
                   const cv::Mat& precomputed_flow = cv::Mat(), const std::vector<cv::Point2f>& predicted = {});
  // The same between images whose pyramids BuildGreyPyramid() built with this tracker's parameters.
  FlowResult track(const GreyPyramid& prev, const GreyPyramid& curr, const std::vector<cv::Point2f>& prev_points,
                   const cv::Mat& precomputed_flow = cv::Mat(), const std::vector<cv::Point2f>& predicted = {});

  // Lucas-Kanade only (else std::invalid_argument), started at `predicted` (one per point) with two
  // pyramid levels, both ways. For points whose motion model is trusted but which the full pyramid lost:
  // near the image border or an occluding edge, its coarse levels see mostly what is not the point's
  // neighbourhood (a car leaving the view at 100 px a frame).
  FlowResult trackNearPrediction(const GreyPyramid& prev, const GreyPyramid& curr,
                                 const std::vector<cv::Point2f>& prev_points,
                                 const std::vector<cv::Point2f>& predicted) const;

  // The dense prev -> curr field of the last track() call (DIS and precomputed; empty for LK).
  const cv::Mat& lastDenseFlow() const { return dense_forward_; }

 private:
  FlowParams params_;
  cv::Mat dense_forward_;
  struct Dis;
  std::unique_ptr<Dis> dis_;
  struct Orb;
  std::unique_ptr<Orb> orb_;
  FlowResult LucasKanadeBothWays(const GreyPyramid& prev, const GreyPyramid& curr,
                                 const std::vector<cv::Point2f>& prev_points, const std::vector<cv::Point2f>& predicted,
                                 int levels) const;
  FlowResult trackByDescriptors(const cv::Mat& prev_gray, const cv::Mat& curr_gray,
                                const std::vector<cv::Point2f>& prev_points);
};

}  // namespace dslam
