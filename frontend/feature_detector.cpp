#include "frontend/feature_detector.h"

#include <algorithm>
#include <stdexcept>

#include <opencv2/features2d.hpp>

namespace dslam {

void FeatureGridParams::validate() const {
  if (cell_px < 4) throw std::invalid_argument("feature grid cell_px must be >= 4");
  if (per_cell < 1) throw std::invalid_argument("feature grid per_cell must be >= 1");
  if (fast_threshold < 1 || fast_threshold > 255) throw std::invalid_argument("fast_threshold must be in 1..255");
  if (!(min_distance_px >= 0.0)) throw std::invalid_argument("feature min_distance_px must be >= 0");
}

namespace {

// FAST's Bresenham circle has radius 3: no corner is found closer than this to an image's border.
constexpr int kFastBorderPx = 3;

// Points per grid cell, with the positions kept for the minimum-distance test.
class CellIndex {
 public:
  CellIndex(const cv::Size& image, int cell_px)
      : cell_(cell_px), cols_((image.width + cell_px - 1) / cell_px), rows_((image.height + cell_px - 1) / cell_px),
        cells_(static_cast<size_t>(cols_ * rows_)) {}
  int count(const cv::Point2f& p) const { return static_cast<int>(cells_[index(cellOf(p))].size()); }
  void add(const cv::Point2f& p) {
    const cv::Point c = cellOf(p);
    if (c.x >= 0 && c.x < cols_ && c.y >= 0 && c.y < rows_) cells_[index(c)].push_back(p);
  }
  bool near(const cv::Point2f& p, double min_distance) const {
    const cv::Point c = cellOf(p);
    const int reach = static_cast<int>(min_distance / cell_) + 1;
    for (int y = std::max(0, c.y - reach); y <= std::min(rows_ - 1, c.y + reach); ++y)
      for (int x = std::max(0, c.x - reach); x <= std::min(cols_ - 1, c.x + reach); ++x)
        for (const cv::Point2f& q : cells_[index({x, y})])
          if (cv::norm(p - q) < min_distance) return true;
    return false;
  }

 private:
  cv::Point cellOf(const cv::Point2f& p) const {
    return {std::clamp(static_cast<int>(p.x) / cell_, 0, cols_ - 1), std::clamp(static_cast<int>(p.y) / cell_, 0, rows_ - 1)};
  }
  size_t index(const cv::Point& c) const { return static_cast<size_t>(c.y * cols_ + c.x); }
  int cell_, cols_, rows_;
  std::vector<std::vector<cv::Point2f>> cells_;
};

}  // namespace

std::vector<cv::KeyPoint> DetectFastCorners(const cv::Mat& gray, int threshold) {
  if (gray.type() != CV_8UC1) throw std::invalid_argument("feature detection needs an 8-bit grey image");
  if (threshold < 1 || threshold > 255) throw std::invalid_argument("fast_threshold must be in 1..255");
  std::vector<cv::KeyPoint> corners;
  cv::FastFeatureDetector::create(threshold, true)->detect(gray, corners);
  // Equal responses in image order: the selection must not depend on which other corners were detected.
  std::sort(corners.begin(), corners.end(), [](const cv::KeyPoint& a, const cv::KeyPoint& b) {
    if (a.response != b.response) return a.response > b.response;
    return a.pt.y != b.pt.y ? a.pt.y < b.pt.y : a.pt.x < b.pt.x;
  });
  return corners;
}

std::vector<cv::Point2f> SelectOnGrid(const std::vector<cv::KeyPoint>& corners, const cv::Rect& region,
                                      const cv::Mat& allowed, const std::vector<cv::Point2f>& existing,
                                      const FeatureGridParams& params) {
  params.validate();
  if (!allowed.empty() && (allowed.type() != CV_8UC1 || allowed.size() != region.size()))
    throw std::invalid_argument("feature mask must be CV_8UC1 of the region's size");
  const cv::Point2f origin(static_cast<float>(region.x), static_cast<float>(region.y));
  CellIndex index(region.size(), params.cell_px);
  for (const cv::Point2f& p : existing) index.add(p - origin);
  std::vector<cv::Point2f> found;
  for (const cv::KeyPoint& kp : corners) {
    if (kp.response < params.fast_threshold) break;  // strongest first: the rest respond less
    const cv::Point2f p = kp.pt - origin;
    const int u = static_cast<int>(p.x), v = static_cast<int>(p.y);
    // FAST's own border: what a detection on the region alone could find (the circle fits in it).
    if (u < kFastBorderPx || v < kFastBorderPx || u >= region.width - kFastBorderPx || v >= region.height - kFastBorderPx)
      continue;
    if (!allowed.empty() && !allowed.at<uint8_t>(v, u)) continue;
    if (index.count(p) >= params.per_cell || index.near(p, params.min_distance_px)) continue;
    index.add(p);
    found.push_back(kp.pt);
  }
  return found;
}

std::vector<cv::Point2f> DetectOnGrid(const cv::Mat& gray, const cv::Mat& allowed, const std::vector<cv::Point2f>& existing,
                                      const FeatureGridParams& params) {
  params.validate();
  if (gray.type() != CV_8UC1) throw std::invalid_argument("feature detection needs an 8-bit grey image");
  if (!allowed.empty() && (allowed.type() != CV_8UC1 || allowed.size() != gray.size()))
    throw std::invalid_argument("feature mask must be CV_8UC1 of the image size");
  return SelectOnGrid(DetectFastCorners(gray, params.fast_threshold), cv::Rect(0, 0, gray.cols, gray.rows), allowed,
                      existing, params);
}

std::vector<cv::Point2f> SampleLattice(const cv::Mat& allowed, const cv::Rect& region, int step_px) {
  if (step_px < 1) throw std::invalid_argument("lattice step must be >= 1");
  std::vector<cv::Point2f> points;
  const cv::Rect r = region & cv::Rect(0, 0, allowed.cols, allowed.rows);
  for (int v = r.y + step_px / 2; v < r.y + r.height; v += step_px) {
    const uint8_t* row = allowed.ptr<uint8_t>(v);
    for (int u = r.x + step_px / 2; u < r.x + r.width; u += step_px)
      if (row[u]) points.emplace_back(static_cast<float>(u), static_cast<float>(v));
  }
  return points;
}

}  // namespace dslam
