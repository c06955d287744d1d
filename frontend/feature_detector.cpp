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

// FAST's circle has radius 3, and its non-maximum suppression compares each corner with its 8
// neighbours: a detection on a region grown by this margin finds, inside the region, exactly the corners
// a detection on the whole image finds there.
constexpr int kFastMarginPx = 4;

// Points per grid cell, with the positions kept for the minimum-distance test.
class CellIndex {
 public:
  CellIndex(const cv::Size& image, int cell_px)
      : cell_(cell_px), cols_((image.width + cell_px - 1) / cell_px), rows_((image.height + cell_px - 1) / cell_px),
        cells_(static_cast<size_t>(cols_ * rows_)) {}
  int cols() const { return cols_; }
  int rows() const { return rows_; }
  int count(const cv::Point2f& p) const { return static_cast<int>(cells_[index(cellOf(p))].size()); }
  int countAt(int x, int y) const { return static_cast<int>(cells_[index({x, y})].size()); }
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

// The image rectangles whose cells can still take a feature (fewer than per_cell points, some pixel
// allowed): runs of such cells along each row of cells, and runs that repeat in the next row of cells
// merged into one rectangle, so that a grid with every cell open is one rectangle, the image.
std::vector<cv::Rect> OpenRegions(const CellIndex& index, const cv::Mat& allowed, const cv::Size& image,
                                  const FeatureGridParams& params) {
  std::vector<cv::Rect> regions;
  std::vector<std::pair<int, int>> previous_runs;  // [first, last] cell columns of the last row's runs
  std::vector<size_t> previous_region;             // their regions
  for (int y = 0; y < index.rows(); ++y) {
    std::vector<std::pair<int, int>> runs;
    for (int x = 0; x < index.cols(); ++x) {
      const cv::Rect cell = cv::Rect(x * params.cell_px, y * params.cell_px, params.cell_px, params.cell_px) &
                            cv::Rect(0, 0, image.width, image.height);
      const bool open = index.countAt(x, y) < params.per_cell && (allowed.empty() || cv::countNonZero(allowed(cell)) > 0);
      if (!open) continue;
      if (!runs.empty() && runs.back().second == x - 1)
        runs.back().second = x;
      else
        runs.emplace_back(x, x);
    }
    std::vector<size_t> region_of_run;
    for (const auto& run : runs) {
      const cv::Rect cells(run.first * params.cell_px, y * params.cell_px, (run.second - run.first + 1) * params.cell_px,
                           params.cell_px);
      const auto same = std::find(previous_runs.begin(), previous_runs.end(), run);
      if (same != previous_runs.end()) {
        const size_t r = previous_region[static_cast<size_t>(same - previous_runs.begin())];
        regions[r] |= cells;
        region_of_run.push_back(r);
      } else {
        regions.push_back(cells);
        region_of_run.push_back(regions.size() - 1);
      }
    }
    previous_runs = std::move(runs);
    previous_region = std::move(region_of_run);
  }
  for (cv::Rect& r : regions) r &= cv::Rect(0, 0, image.width, image.height);
  return regions;
}

}  // namespace

std::vector<cv::Point2f> DetectOnGrid(const cv::Mat& gray, const cv::Mat& allowed, const std::vector<cv::Point2f>& existing,
                                      const FeatureGridParams& params) {
  params.validate();
  if (gray.type() != CV_8UC1) throw std::invalid_argument("feature detection needs an 8-bit grey image");
  if (!allowed.empty() && (allowed.type() != CV_8UC1 || allowed.size() != gray.size()))
    throw std::invalid_argument("feature mask must be CV_8UC1 of the image size");
  CellIndex index(gray.size(), params.cell_px);
  for (const cv::Point2f& p : existing) index.add(p);

  // Corners only where a cell can take one: once the tracks fill most cells, most of the image is not
  // searched (FAST is most of the detection's time). The selection is the same as over the whole image.
  const cv::Rect image(0, 0, gray.cols, gray.rows);
  const cv::Ptr<cv::FastFeatureDetector> fast = cv::FastFeatureDetector::create(params.fast_threshold, true);
  std::vector<cv::KeyPoint> corners;
  for (const cv::Rect& region : OpenRegions(index, allowed, gray.size(), params)) {
    const cv::Rect grown =
        cv::Rect(region.x - kFastMarginPx, region.y - kFastMarginPx, region.width + 2 * kFastMarginPx,
                 region.height + 2 * kFastMarginPx) & image;
    std::vector<cv::KeyPoint> found;
    fast->detect(gray(grown), found);
    for (cv::KeyPoint& kp : found) {
      kp.pt += cv::Point2f(static_cast<float>(grown.x), static_cast<float>(grown.y));
      const cv::Point px(static_cast<int>(kp.pt.x), static_cast<int>(kp.pt.y));
      if (region.contains(px) && (allowed.empty() || allowed.at<uint8_t>(px))) corners.push_back(kp);
    }
  }
  // Strongest first; equal responses in image order, so that the choice does not depend on the regions.
  std::sort(corners.begin(), corners.end(), [](const cv::KeyPoint& a, const cv::KeyPoint& b) {
    if (a.response != b.response) return a.response > b.response;
    return a.pt.y != b.pt.y ? a.pt.y < b.pt.y : a.pt.x < b.pt.x;
  });
  std::vector<cv::Point2f> points;
  for (const cv::KeyPoint& kp : corners) {
    if (index.count(kp.pt) >= params.per_cell || index.near(kp.pt, params.min_distance_px)) continue;
    index.add(kp.pt);
    points.push_back(kp.pt);
  }
  return points;
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
