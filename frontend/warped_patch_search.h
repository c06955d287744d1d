#pragma once
// Finds points whose image appearance changed too much for Lucas-Kanade: a car passing close to the
// camera shows its side at a grazing angle, and between two frames that side stretches by half and
// shears while it moves 100-200 px. Given where a motion model puts each point and how it maps the
// point's neighbourhood (the local affine map of the predicted 3D motion), the previous image's patch
// is warped into the current frame's geometry and searched for by normalised cross-correlation
// around the prediction, then refined by Lucas-Kanade on a larger warped patch, which must correlate as
// well. A match must be strong and unique: on a repetitive texture the second-best peak comes close to
// the best, and such a point is left lost.

#include <vector>

#include <opencv2/core.hpp>

namespace dslam {

struct WarpedSearchParams {
  int radius_px = 24;      // how far from the prediction the match may lie, or a third of the predicted
                           // move when that is more (up to 64 px); 0: no search
  int half_patch_px = 7;   // the template is (2 half + 1) px square
  double min_ncc = 0.85;   // normalised cross-correlation of an accepted match
  double min_margin = 0.1;  // the best peak must beat every other local maximum by this
  // The front-end asks for a search only where the predicted motion deforms the neighbourhood by at
  // least this (the largest entry of A - I: a stretch, squeeze or shear of 30 %); elsewhere
  // Lucas-Kanade's model holds, and a track it lost is lost for another reason (an occlusion, a contour).
  double min_deformation = 0.3;
  // Where the motion deforms the patch by at least this (a stretch or shear of 60 %, where Lucas-Kanade
  // from the same start finds at most 6 of 42 points of a random texture), a flow match that the search
  // does not confirm is dropped: it is more likely a look-alike than the point (rendered 0005: 19 tracks
  // of a car 5 m away, slid near their prediction, agreed on a speed 26 % off).
  double max_flow_deformation = 0.6;
  void validate() const;
};

struct WarpedPatchRequest {
  cv::Point2f prev_px;       // the point in the previous image
  cv::Point2f predicted_px;  // where the motion model puts it in the current one
  cv::Matx22f A;             // d(current px) / d(previous px) around it: how its neighbourhood maps
};

struct WarpedPatchMatch {
  bool ok = false;
  cv::Point2f px;   // in the current image, sub-pixel
  float ncc = 0.f;  // of the larger patch at the refined position
};

// prev_gray, curr_gray: CV_8UC1 of one size (else std::invalid_argument, as for invalid params). One
// match per request, in order.
std::vector<WarpedPatchMatch> SearchWarpedPatches(const cv::Mat& prev_gray, const cv::Mat& curr_gray,
                                                  const std::vector<WarpedPatchRequest>& requests,
                                                  const WarpedSearchParams& params);

}  // namespace dslam
