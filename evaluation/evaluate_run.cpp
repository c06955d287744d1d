#include "evaluation/evaluate_run.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include "geometry/velocity.h"

namespace dslam {

std::optional<ObjectPairSample> GroundTruthPair(const GroundTruth& gt, double frame_rate_hz, int object_id, int k) {
  const auto it = gt.objects.find(object_id);
  if (it == gt.objects.end()) return std::nullopt;
  const ObjectGroundTruth& obj = it->second;
  if (!obj.observed_frames.count(k) || !obj.observed_frames.count(k - 1)) return std::nullopt;
  ObjectPairSample s;
  s.object_id = object_id;
  s.frame = k;
  const SE3& L_prev = obj.L_world_object.at(k - 1);
  s.L_world_object_gt_prev = L_prev;
  s.H_world_gt = obj.L_world_object.at(k) * L_prev.inverse();
  const Vec3& c_prev = obj.centroid_world.at(k - 1);
  s.speed_gt_mps = (s.H_world_gt * c_prev - c_prev).norm() * frame_rate_hz;
  // Over the frames k-h .. k-1+h (h = half a second of frames) where the object has a pose: about a second
  // centred on the pair, shorter at the ends of its track.
  const int h = std::max(1, static_cast<int>(std::lround(0.5 * frame_rate_hz)));
  const auto first = obj.centroid_world.lower_bound(k - h);
  auto last = obj.centroid_world.upper_bound(k - 1 + h);
  --last;  // k is in the map: the pair has poses
  s.window_speed_gt_mps = first->first < last->first ? (last->second - first->second).norm() * frame_rate_hz /
                                                            static_cast<double>(last->first - first->first)
                                                      : s.speed_gt_mps;
  if (obj.measurable_frames) s.measurable = obj.measurable_frames->count(k) > 0;
  return s;
}

void SetEstimate(const ObjectMotionEstimate& motion, ObjectPairSample* s) {
  s->estimated = true;
  s->H_world_est = motion.H_world;
  s->speed_est_mps = motion.speed_mps;
  s->est_dynamic = motion.is_dynamic;
  s->covariance_est = motion.covariance;
  s->anchor_est = motion.anchor_world;
  s->speed_sigma_est_mps = motion.speed_sigma_mps;
}

int RunObjectId(const GroundTruth& gt, int gt_id, int frame) {
  if (!gt.run_object_ids) return gt_id;
  const auto now = gt.run_object_ids->find({frame, gt_id}), before = gt.run_object_ids->find({frame - 1, gt_id});
  if (now == gt.run_object_ids->end() || before == gt.run_object_ids->end() || now->second != before->second) return 0;
  return now->second;
}

std::optional<int> GroundTruthIdOf(const GroundTruth& gt, int run_id, int frame) {
  if (!gt.run_object_ids) return run_id;
  if (run_id == 0) return std::nullopt;  // RunObjectId's "no estimate"
  for (const auto& [gt_id, obj] : gt.objects)
    if (RunObjectId(gt, gt_id, frame) == run_id) return gt_id;
  return std::nullopt;
}

std::vector<ObjectPairSample> BuildObjectSamples(const Sequence& seq, const Estimate& est, const std::string& category) {
  std::map<std::pair<int, int>, const ObjectMotionEstimate*> by_key;
  for (const auto& m : est.object_motions) by_key[{m.object_id, m.frame}] = &m;
  std::vector<ObjectPairSample> samples;
  for (const auto& [id, obj] : seq.gt.objects) {
    if (!category.empty() && obj.category != category) continue;
    for (int k : obj.observed_frames) {
      std::optional<ObjectPairSample> s = GroundTruthPair(seq.gt, seq.frame_rate_hz, id, k);
      if (!s) continue;
      const auto it = by_key.find({RunObjectId(seq.gt, id, k), k});
      if (it != by_key.end()) SetEstimate(*it->second, &*s);
      samples.push_back(*s);
    }
  }
  return samples;
}

MethodMetrics EvaluateEstimate(const Sequence& seq, const Estimate& est, bool estimates_objects,
                               const std::string& category) {
  MethodMetrics m;
  m.camera = ComputeCameraMetrics(seq.gt.T_world_camera, est.T_world_camera, est.camera_step_covariance);
  RseAccumulator rse;
  for (const auto& p : est.points) {
    Vec3 p_gt_world;
    if (!seq.gt.pointWorld(p.track_id, p.frame, &p_gt_world)) continue;
    rse.add(est.T_world_camera[p.frame].inverse() * p.p_world, seq.gt.T_world_camera[p.frame].inverse() * p_gt_world);
  }
  m.rse_pct = rse.result();
  if (estimates_objects) m.objects = ComputeObjectMetrics(BuildObjectSamples(seq, est, category));
  return m;
}

void ObjectSummaries::add(const ObjectPairSample& s, const std::string& category) {
  addPair(s, category);
  if (s.estimated) addEstimate(s);
}

void ObjectSummaries::addPair(const ObjectPairSample& pair, const std::string& category) {
  PerObject& o = objects_[pair.object_id];
  o.category = category;
  o.metrics.addPair(pair);
}

void ObjectSummaries::addEstimate(const ObjectPairSample& s) {
  PerObject& o = objects_[s.object_id];
  o.metrics.addEstimate(s);
  o.sum_gt_mps += s.speed_gt_mps;
  o.sum_est_mps += s.speed_est_mps;
}

std::vector<ObjectSummary> ObjectSummaries::result() const {
  std::vector<ObjectSummary> out;
  for (const auto& [id, o] : objects_) {
    ObjectSummary summary;
    summary.object_id = id;
    summary.category = o.category;
    summary.metrics = o.metrics.result();
    summary.gt_pairs = summary.metrics.gt_pairs;
    summary.frames_estimated = summary.metrics.estimated_pairs;
    if (summary.frames_estimated > 0) {
      summary.mean_gt_speed_kmh = o.sum_gt_mps / summary.frames_estimated * kMpsToKmh;
      summary.mean_est_speed_kmh = o.sum_est_mps / summary.frames_estimated * kMpsToKmh;
    }
    out.push_back(summary);
  }
  return out;
}

std::vector<ObjectSummary> SummariseObjects(const Sequence& seq, const Estimate& est) {
  ObjectSummaries summaries;
  for (const auto& s : BuildObjectSamples(seq, est)) summaries.add(s, seq.gt.objects.at(s.object_id).category);
  return summaries.result();
}

}  // namespace dslam
