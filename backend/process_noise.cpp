#include "backend/process_noise.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <unordered_set>

#include "backend/factors/motion_smoothness_factor.h"

namespace dslam {
namespace {

Vec6 ConfiguredSigma(const BackendParams& params) {
  Vec6 sigma;
  sigma << Vec3::Constant(params.noise.smoothness_sigma_t_m), Vec3::Constant(params.noise.smoothness_sigma_r_rad);
  return sigma;
}

int ObjectOf(const FactorGraph& graph, const SmoothnessEntry& s) { return graph.motions.at(s.curr_motion_var).object_id; }

void Add(const Vec6& r, SmoothnessResiduals* sums) {
  sums->sum_sq_t += r.head<3>().squaredNorm();
  sums->sum_sq_r += r.tail<3>().squaredNorm();
  ++sums->count;
}

}  // namespace

Vec6 SmoothnessSigma(const BackendParams& params, const FactorGraph& graph, int object_id) {
  Vec6 sigma = ConfiguredSigma(params);
  const auto it = graph.smoothness_noise.find(object_id);
  if (it != graph.smoothness_noise.end()) {
    sigma.head<3>() *= it->second.scale_t;
    sigma.tail<3>() *= it->second.scale_r;
  }
  return sigma;
}

Vec6 ConfiguredSmoothnessResidual(const BackendParams& params, const FactorGraph& graph, const SmoothnessEntry& s) {
  const MotionVariable& curr = graph.motions.at(s.curr_motion_var);
  const bool prev_live = s.prev_motion_var >= 0;
  const double* H_prev = prev_live ? graph.motions.at(s.prev_motion_var).H_anchor.data() : s.prev_fixed.data();
  const Vec3 anchor_prev = prev_live ? graph.motions.at(s.prev_motion_var).anchor_world : s.prev_fixed_anchor;
  Vec6 r;
  MotionSmoothnessFactor(ConfiguredSigma(params), anchor_prev, curr.anchor_world)(H_prev, curr.H_anchor.data(), r.data());
  return r;
}

void AccumulateLeavingSmoothness(const BackendParams& params, int frame, FactorGraph* graph) {
  if (!params.noise.smoothness_from_residuals || frame < graph->first_stored_frame || frame >= graph->numFrames())
    return;
  for (const SmoothnessEntry& s : graph->frame(frame).smoothness) {
    if (graph->motions.at(s.curr_motion_var).last_frame > frame) continue;  // its motion stays
    AccumulateFinalSmoothness(params, s, graph);
  }
}

void AccumulateFinalSmoothness(const BackendParams& params, const SmoothnessEntry& s, FactorGraph* graph) {
  if (!params.noise.smoothness_from_residuals) return;
  Add(ConfiguredSmoothnessResidual(params, *graph, s), &graph->smoothness_noise[ObjectOf(*graph, s)].final);
}

void ForgetObjectsWithoutMotions(FactorGraph* graph) {
  if (graph->smoothness_noise.empty()) return;  // the option is off, or no object has a scale yet
  std::unordered_set<int> objects_with_motions;
  for (const auto& [id, motion] : graph->motions) objects_with_motions.insert(motion.object_id);
  for (auto it = graph->smoothness_noise.begin(); it != graph->smoothness_noise.end();)
    it = objects_with_motions.count(it->first) ? std::next(it) : graph->smoothness_noise.erase(it);
}

double UpdateSmoothnessScales(const BackendParams& params, int first_frame, int last_frame, FactorGraph* graph) {
  if (!params.noise.smoothness_from_residuals) return 0.0;
  std::unordered_map<int, SmoothnessResiduals> in_window;  // by object
  for (int k = std::max(first_frame, graph->first_stored_frame); k <= std::min(last_frame, graph->numFrames() - 1); ++k)
    for (const SmoothnessEntry& s : graph->frame(k).smoothness)
      Add(ConfiguredSmoothnessResidual(params, *graph, s), &in_window[ObjectOf(*graph, s)]);
  auto scale_of = [](double sum_sq, int count) { return std::sqrt(std::max(1.0, sum_sq / (3.0 * count))); };
  double largest_change = 0.0;
  for (const auto& [object_id, window] : in_window) {
    SmoothnessNoise& noise = graph->smoothness_noise[object_id];
    const int count = noise.final.count + window.count;
    if (count < kMinSmoothnessFactorsForScale) continue;
    const double scale_t = scale_of(noise.final.sum_sq_t + window.sum_sq_t, count);
    const double scale_r = scale_of(noise.final.sum_sq_r + window.sum_sq_r, count);
    largest_change = std::max({largest_change, std::abs(scale_t - noise.scale_t) / noise.scale_t,
                               std::abs(scale_r - noise.scale_r) / noise.scale_r});
    noise.scale_t = scale_t;
    noise.scale_r = scale_r;
  }
  return largest_change;
}

}  // namespace dslam
