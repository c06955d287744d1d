#include "pipeline/reference_objects.h"

#include <algorithm>
#include <unordered_map>

namespace dslam {

ReferenceObjectMatcher::ReferenceObjectMatcher(const PinholeCamera& camera, double min_mask_area_pct)
    : camera_(camera), min_mask_area_pct_(min_mask_area_pct) {}

void ReferenceObjectMatcher::keep(int frame, cv::Mat ids) {
  std::lock_guard<std::mutex> lock(kept_mutex_);
  kept_[frame] = std::move(ids);
}

void ReferenceObjectMatcher::match(int frame, const FrameMeasurement& measurement) {
  cv::Mat ids;
  {
    std::lock_guard<std::mutex> lock(kept_mutex_);
    const auto it = kept_.find(frame);
    if (it == kept_.end()) return;
    ids = it->second;
    kept_.erase(it);
  }
  cv::Mat labels;
  ids.convertTo(labels, CV_32S);
  std::unordered_map<int, int> area;
  for (int v = 0; v < labels.rows; ++v) {
    const int* row = labels.ptr<int>(v);
    for (int u = 0; u < labels.cols; ++u)
      if (row[u] > 0) ++area[row[u]];
  }
  const double min_area = min_mask_area_pct_ / 100.0 * static_cast<double>(labels.total());
  for (const auto& [label, pixels] : area)
    if (pixels >= min_area) visible_.insert({frame, label});

  std::map<int, std::pair<int, int>> best;  // reference id -> (points in it, run id)
  for (const ObjectObservation& obs : measurement.objects) {
    std::map<int, int> votes;
    for (const PointObservation& p : obs.points) {
      if (!(p.p_camera.z() > 0.0)) continue;
      const Vec2 uv = camera_.project(p.p_camera);
      const int u = static_cast<int>(uv.x()), v = static_cast<int>(uv.y());
      if (u < 0 || v < 0 || u >= labels.cols || v >= labels.rows) continue;
      if (const int label = labels.at<int>(v, u); label > 0) ++votes[label];
    }
    const auto top = std::max_element(votes.begin(), votes.end(),
                                      [](const auto& a, const auto& b) { return a.second < b.second; });
    if (top == votes.end() || 2 * top->second < static_cast<int>(obs.points.size())) continue;
    auto& slot = best[top->first];
    if (top->second > slot.first) slot = {top->second, obs.object_id};
  }
  for (const auto& [reference_id, choice] : best) run_object_ids_[{frame, reference_id}] = choice.second;
}

}  // namespace dslam
