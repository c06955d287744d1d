#pragma once
// Which ground-truth object each of a run's objects is, when the run's masks are its own (made from the
// LiDAR, say) but the dataset has exact masks too: each frame's exact mask is kept until the front-end's
// measurement of that frame arrives; a run object is the reference object that at least half of its
// measured points fall in (one run object per reference object: the one with the most points there).
// Its result is GroundTruth::run_object_ids. Frames may be kept from one thread and matched on another.

#include <map>
#include <mutex>
#include <set>
#include <utility>

#include <opencv2/core.hpp>

#include "data/measurements.h"
#include "geometry/pinhole_camera.h"

namespace dslam {

class ReferenceObjectMatcher {
 public:
  // `min_mask_area_pct`: reference objects smaller than this share of the image do not count as visible
  // (the front-end's own threshold for masks).
  ReferenceObjectMatcher(const PinholeCamera& camera, double min_mask_area_pct);

  // Frame k's exact instance ids (CV_16U or CV_32S, 0 = background), until match(k, ...) takes them.
  void keep(int frame, cv::Mat ids);
  // Matches frame k's run objects to the kept mask of frame k (nothing when none was kept).
  void match(int frame, const FrameMeasurement& measurement);

  // Reference objects of at least the minimum area in frame k's exact mask.
  bool visible(int frame, int reference_id) const { return visible_.count({frame, reference_id}) > 0; }
  // (frame, reference id) -> the run's object id there.
  const std::map<std::pair<int, int>, int>& runObjectIds() const { return run_object_ids_; }

 private:
  PinholeCamera camera_;
  double min_mask_area_pct_;
  std::mutex kept_mutex_;
  std::map<int, cv::Mat> kept_;  // frames read but not yet through the front-end
  std::set<std::pair<int, int>> visible_;
  std::map<std::pair<int, int>, int> run_object_ids_;
};

}  // namespace dslam
