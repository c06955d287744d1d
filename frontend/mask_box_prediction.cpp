#include "frontend/mask_box_prediction.h"

namespace dslam {

cv::Point2f PredictFromMaskBoxes(const cv::Rect& before, const cv::Rect& now, const cv::Point2f& px, int width,
                                 int height) {
  const auto cut_low_x = [](const cv::Rect& r) { return r.x <= 0; };
  const auto cut_high_x = [width](const cv::Rect& r) { return r.x + r.width >= width; };
  const auto cut_low_y = [](const cv::Rect& r) { return r.y <= 0; };
  const auto cut_high_y = [height](const cv::Rect& r) { return r.y + r.height >= height; };
  const bool low_x = cut_low_x(before) || cut_low_x(now), high_x = cut_high_x(before) || cut_high_x(now);
  const bool low_y = cut_low_y(before) || cut_low_y(now), high_y = cut_high_y(before) || cut_high_y(now);
  const float sx = static_cast<float>(now.width) / static_cast<float>(before.width);
  const float sy = static_cast<float>(now.height) / static_cast<float>(before.height);
  const float scale_x = !(low_x || high_x) ? sx : !(low_y || high_y) ? sy : 1.0f;
  const float scale_y = !(low_y || high_y) ? sy : !(low_x || high_x) ? sx : 1.0f;
  // Anchored on the edge the border does not cut (the low edge when neither or both are cut).
  const float x = low_x && !high_x ? (now.x + now.width) + (px.x - (before.x + before.width)) * scale_x
                                   : now.x + (px.x - before.x) * scale_x;
  const float y = low_y && !high_y ? (now.y + now.height) + (px.y - (before.y + before.height)) * scale_y
                                   : now.y + (px.y - before.y) * scale_y;
  return {x, y};
}

}  // namespace dslam
