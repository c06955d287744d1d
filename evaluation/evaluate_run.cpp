#include "evaluation/evaluate_run.h"

#include <map>
#include <utility>

namespace dslam {

std::vector<ObjectPairSample> BuildObjectSamples(const Sequence& seq, const Estimate& est, const std::string& category) {
  std::map<std::pair<int, int>, const ObjectMotionEstimate*> by_key;
  for (const auto& m : est.object_motions) by_key[{m.object_id, m.frame}] = &m;
  std::vector<ObjectPairSample> samples;
  for (const auto& [id, obj] : seq.gt.objects) {
    if (!category.empty() && obj.category != category) continue;
    for (int k : obj.observed_frames) {
      if (!obj.observed_frames.count(k - 1)) continue;
      ObjectPairSample s;
      s.object_id = id;
      s.frame = k;
      const SE3& L_prev = obj.L_world_object.at(k - 1);
      s.L_world_object_gt_prev = L_prev;
      s.H_world_gt = obj.L_world_object.at(k) * L_prev.inverse();
      const Vec3& c_prev = obj.centroid_world.at(k - 1);
      s.speed_gt_mps = (s.H_world_gt * c_prev - c_prev).norm() * seq.frame_rate_hz;
      const auto it = by_key.find({id, k});
      if (it != by_key.end()) {
        s.estimated = true;
        s.H_world_est = it->second->H_world;
        s.speed_est_mps = it->second->speed_mps;
        s.est_dynamic = it->second->is_dynamic;
        s.covariance_est = it->second->covariance;
        s.speed_sigma_est_mps = it->second->speed_sigma_mps;
      }
      samples.push_back(s);
    }
  }
  return samples;
}

MethodMetrics EvaluateEstimate(const Sequence& seq, const Estimate& est, bool estimates_objects,
                               const std::string& category) {
  MethodMetrics m;
  m.camera = ComputeCameraMetrics(seq.gt.T_world_camera, est.T_world_camera);
  std::vector<std::pair<Vec3, Vec3>> structure;
  structure.reserve(est.points.size());
  for (const auto& p : est.points) {
    Vec3 p_gt_world;
    if (!seq.gt.pointWorld(p.track_id, p.frame, &p_gt_world)) continue;
    structure.emplace_back(est.T_world_camera[p.frame].inverse() * p.p_world,
                           seq.gt.T_world_camera[p.frame].inverse() * p_gt_world);
  }
  m.rse_pct = ComputeRsePct(structure);
  if (estimates_objects) m.objects = ComputeObjectMetrics(BuildObjectSamples(seq, est, category));
  return m;
}

}  // namespace dslam
