#pragma once
// New features on a grid: FAST corners, strongest first, at most `per_cell` in each cell of the image
// grid (counting the points already tracked there) and never closer than `min_distance_px` to another
// point, so that the features spread over the image instead of piling up on the most textured patch.
// Only the cells that can still take a feature are searched (the result is that of a search of the whole
// image), so that detection costs little once the tracks fill the grid.

#include <vector>

#include <opencv2/core.hpp>

namespace dslam {

struct FeatureGridParams {
  int cell_px = 32;
  int per_cell = 2;
  int fast_threshold = 10;
  double min_distance_px = 8.0;
  void validate() const;
};

// gray: CV_8UC1; allowed: CV_8UC1 of the same size, non-zero where a new feature may go (empty: anywhere).
std::vector<cv::Point2f> DetectOnGrid(const cv::Mat& gray, const cv::Mat& allowed, const std::vector<cv::Point2f>& existing,
                                      const FeatureGridParams& params);


// Pixels on a regular lattice with `step_px` spacing where `allowed` is non-zero: points for regions
// without corners (an untextured car door still moves with the car).
std::vector<cv::Point2f> SampleLattice(const cv::Mat& allowed, const cv::Rect& region, int step_px);

}  // namespace dslam
