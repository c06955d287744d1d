#pragma once
// Where a point of an instance mask is too near another label to be trusted: pixels there mix the depths
// of object and background, and a point tracked there may be sliding along an occluding contour.

#include <opencv2/core.hpp>

namespace dslam {

// labels: CV_32SC1 (0 = background). Non-zero (CV_8UC1, 255) where the (2 border_px + 1)-square window
// around the pixel, clipped at the image border, holds more than one label; all zero for border_px <= 0.
cv::Mat NearMaskEdge(const cv::Mat& labels, int border_px);

}  // namespace dslam
