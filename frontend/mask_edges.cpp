#include "frontend/mask_edges.h"

#include <stdexcept>

#include <opencv2/imgproc.hpp>

namespace dslam {

cv::Mat NearMaskEdge(const cv::Mat& labels, int border_px) {
  if (labels.type() != CV_32SC1) throw std::invalid_argument("NearMaskEdge needs CV_32SC1 labels");
  if (border_px <= 0 || labels.empty()) return cv::Mat(labels.size(), CV_8UC1, cv::Scalar(0));
  // A window holds two labels exactly when two 4-neighbours inside it differ (a window is 4-connected).
  // So: mark each pair of neighbours that differ at its left (or upper) pixel, then spread each mark over
  // the windows that hold its whole pair. Two 8-bit dilations instead of a morphological gradient over
  // the labels as floats (four float passes, and labels above 2^24 merged); ~10x faster on 1242x375.
  cv::Mat right_differs(labels.size(), CV_8UC1, cv::Scalar(0)), below_differs(labels.size(), CV_8UC1, cv::Scalar(0));
  for (int v = 0; v < labels.rows; ++v) {
    const int32_t* row = labels.ptr<int32_t>(v);
    const int32_t* next_row = v + 1 < labels.rows ? labels.ptr<int32_t>(v + 1) : nullptr;
    uint8_t* right = right_differs.ptr<uint8_t>(v);
    uint8_t* below = below_differs.ptr<uint8_t>(v);
    for (int u = 0; u + 1 < labels.cols; ++u) right[u] = row[u] != row[u + 1] ? 255 : 0;
    if (next_row)
      for (int u = 0; u < labels.cols; ++u) below[u] = row[u] != next_row[u] ? 255 : 0;
  }
  // A pair marked at q (q and q + 1 across) lies in the window of p when p.x - b <= q.x <= p.x + b - 1
  // and |p.y - q.y| <= b: a 2b-wide, (2b + 1)-high kernel anchored at (b, b); the vertical pairs alike.
  const int b = border_px;
  cv::Mat near_edge;
  cv::dilate(right_differs, near_edge, cv::Mat::ones(2 * b + 1, 2 * b, CV_8UC1), cv::Point(b, b));
  cv::dilate(below_differs, below_differs, cv::Mat::ones(2 * b, 2 * b + 1, CV_8UC1), cv::Point(b, b));
  near_edge |= below_differs;
  return near_edge;
}

}  // namespace dslam
