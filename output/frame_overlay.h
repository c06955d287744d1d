#pragma once
// A frame as a person checks a run on real images: each instance mask tinted, and each object the run
// estimated in that frame boxed with its id and speed (green: reported moving; grey: standing).

#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "backend/estimate.h"

namespace dslam {

// `instance_ids`: CV_16UC1 or CV_32SC1, or empty; `motions`: the run's estimates of this frame (those
// without an image box are not drawn). Returns a BGR image of the frame's size.
cv::Mat DrawObjectOverlay(const cv::Mat& image, const cv::Mat& instance_ids,
                          const std::vector<ObjectMotionEstimate>& motions);

// The frames of a run of `frames` to show: `count` spread evenly, away from both ends.
std::vector<int> OverlayFrames(int frames, int count);

// Writes `image` to `path` as PNG, whole (a temporary file renamed into place); throws naming the path.
void WriteOverlayPng(const cv::Mat& image, const std::string& path);

}  // namespace dslam
