#pragma once
// How well a point tracker finds correspondences, against the exact ones (the paper's flow-vs-matching
// comparison): Shi-Tomasi corners of frame k (where the exact flow is known) are tracked into frame k+1;
// per tracker the number of matches, of matches on objects, the end-point error (EPE, px) against the
// exact correspondence, and the "good" matches, with an EPE under 3 px.

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "data/image_frame.h"
#include "frontend/flow_tracker.h"

namespace dslam {

struct TrackingScore {
  std::string tracker;     // lk, dis, orb, or "exact"
  int frame_pairs = 0;
  double matches = 0.0;          // per frame pair
  double object_matches = 0.0;   // per frame pair: matches that start on an object's mask
  double good_matches = 0.0;     // per frame pair: EPE < kGoodMatchEpePx
  double mean_epe_px = 0.0;      // over all matches
  double mean_good_epe_px = 0.0; // over the good matches
};
constexpr double kGoodMatchEpePx = 3.0;

class TrackingComparison {
 public:
  // The trackers compared (the exact correspondences are always the first row).
  explicit TrackingComparison(const std::vector<FlowMethod>& trackers, int max_corners = 1500);
  // Frames k and k+1 of a dataset; frame k carries its instance ids (or none) and its exact flow to k+1
  // (flow_to_next, CV_32FC2, components above kUnknownFlow where unknown).
  void add(const ImageFrame& frame_k, const ImageFrame& frame_next);
  std::vector<TrackingScore> scores() const;

 private:
  struct Sums {
    double matches = 0, object_matches = 0, good = 0, epe_sum = 0, good_epe_sum = 0;
  };
  std::vector<FlowMethod> methods_;
  int max_corners_;
  int pairs_ = 0;
  std::vector<Sums> sums_;  // exact first, then one per method
};

}  // namespace dslam
