#include "lidar/lidar_comparison.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

#include "evaluation/metrics.h"

namespace dslam {
namespace {

double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + mid, v.end());
  return v[mid];
}

}  // namespace

LidarReferenceNoise ReferenceNoise(const LidarReference& reference) {
  LidarReferenceNoise noise;
  const auto& d = reference.ego_step_disagreement_m;
  if (d.size() < 2) return noise;
  noise.median_step_m = Median(std::vector<double>(d.begin() + 1, d.end()));
  double path = 0.0, sum = 0.0;
  for (size_t k = 1; k < d.size() && k < reference.T_world_camera.size(); ++k) {
    path += (reference.T_world_camera[k].translation() - reference.T_world_camera[k - 1].translation()).norm();
    sum += d[k];
  }
  if (path > 0.0) noise.summed_pct_of_path = 100.0 * sum / path;
  return noise;
}

LidarCheckReport CompareWithLidar(const LidarReference& reference, const std::vector<SE3>& T_world_camera_run,
                                  const std::vector<RunObjectRow>& rows, const LidarCheckParams& params) {
  LidarCheckReport report;
  const size_t n = std::min(reference.T_world_camera.size(), T_world_camera_run.size());
  if (n < 2) throw std::invalid_argument("the LiDAR check needs at least two frames of both trajectories");
  report.frames = static_cast<int>(n);
  const std::vector<SE3> ref(reference.T_world_camera.begin(), reference.T_world_camera.begin() + n);
  const std::vector<SE3> est(T_world_camera_run.begin(), T_world_camera_run.begin() + n);
  const CameraMetrics m = ComputeCameraMetrics(ref, est);
  report.path_length_m = m.path_length_m;
  report.end_error_m = (ref.back().translation() - est.back().translation()).norm();
  double te = 0.0, re_deg = 0.0;
  for (size_t k = 1; k < n; ++k) {
    const SE3 E = (ref[k - 1].inverse() * ref[k]).inverse() * (est[k - 1].inverse() * est[k]);
    te += E.translation().norm();
    re_deg += Eigen::AngleAxisd(E.rotation()).angle() * 180.0 / M_PI;
  }
  if (m.path_length_m > 0.0) {
    report.end_error_pct = 100.0 * report.end_error_m / m.path_length_m;
    report.rte_pct = 100.0 * te / m.path_length_m;
    report.rre_deg_per_m = re_deg / m.path_length_m;
  }
  report.mean_step_rotation_error_deg = re_deg / static_cast<double>(n - 1);
  report.reference_noise = ReferenceNoise(reference);

  // Each run row at the LiDAR cluster its box overlaps most in that frame, else the one nearest its centroid.
  std::map<int, std::vector<const LidarTrackSample*>> samples_of_frame;
  for (const LidarTrackSample& s : reference.samples) samples_of_frame[s.frame].push_back(&s);
  std::map<std::pair<int, int>, const RunObjectRow*> row_at;  // (frame, track) -> the run's row there
  for (const RunObjectRow& r : rows) {
    if (!r.centroid_camera) continue;
    if (r.moving) ++report.moving_rows;
    const LidarTrackSample* nearest = nullptr;
    if (r.box && r.box->area() > 0) {
      double best_iou = params.match_min_box_iou;
      for (const LidarTrackSample* s : samples_of_frame[r.frame]) {
        const double overlap = (s->box & *r.box).area();
        const double iou = overlap / (s->box.area() + r.box->area() - overlap);
        if (overlap > 0.0 && iou >= best_iou) best_iou = iou, nearest = s;
      }
    }
    double best = params.match_gate_m;
    if (!nearest)
      for (const LidarTrackSample* s : samples_of_frame[r.frame]) {
        const double d = (s->centroid_camera - *r.centroid_camera).norm();
        if (d < best) best = d, nearest = s;
      }
    if (!nearest) {
      report.moving_rows_without_cluster += r.moving;
      continue;
    }
    if (r.moving && nearest->has_speed && nearest->speed_mps < params.standing_speed_mps) ++report.moving_rows_on_standing;
    auto& slot = row_at[{r.frame, nearest->track_id}];
    if (!slot || (r.moving && !slot->moving)) slot = &r;  // two objects on one cluster: the moving one speaks
  }

  std::map<int, std::vector<const LidarTrackSample*>> tracks;
  for (const LidarTrackSample& s : reference.samples) tracks[s.track_id].push_back(&s);
  for (const auto& [id, samples] : tracks) {
    std::vector<double> extents;
    for (const LidarTrackSample* s : samples) extents.push_back(s->extent_m);
    if (Median(extents) < params.vehicle_min_extent_m) continue;
    LidarCheckReport::Vehicle v;
    v.track_id = id;
    std::vector<double> lidar_speeds, differences;
    for (const LidarTrackSample* s : samples) {
      if (s->centroid_camera.norm() > params.vehicle_max_distance_m || !s->has_speed) continue;
      if (s->box.area() <= 0 || s->box.area() < params.vehicle_min_box_fraction * params.image_width * params.image_height)
        continue;
      ++v.frames;
      lidar_speeds.push_back(s->speed_mps);
      const auto it = row_at.find({s->frame, id});
      if (it == row_at.end()) continue;
      ++v.frames_with_speed;
      differences.push_back(std::abs(it->second->speed_mps - s->speed_mps));
      if (it->second->moving && s->speed_mps < params.standing_speed_mps) ++v.moving_while_standing;
    }
    if (v.frames < params.min_track_frames) continue;
    v.coverage = static_cast<double>(v.frames_with_speed) / v.frames;
    v.median_lidar_speed_mps = Median(lidar_speeds);
    if (!differences.empty()) v.median_speed_difference_mps = Median(differences);
    report.vehicles.push_back(v);
  }
  return report;
}

}  // namespace dslam
