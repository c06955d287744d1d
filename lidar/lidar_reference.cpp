#include "lidar/lidar_reference.h"

#include <algorithm>
#include <map>
#include <stdexcept>
#include <string>

namespace dslam {
namespace {

SE3 ToSE3(const Eigen::Isometry3d& T) { return SE3(Mat3(T.linear()), Vec3(T.translation())); }

}  // namespace

ScanRegistrationParams EgoRegistration() {
  ScanRegistrationParams p;
  p.metric = RegistrationMetric::kPointToPlane;
  p.voxel_m = 0.3;
  p.max_correspondence_m = 1.0;
  p.max_iterations = 100;
  p.kept_pair_fraction = 0.7;
  return p;
}

ScanRegistrationParams ObjectRegistration() {
  ScanRegistrationParams p;
  p.metric = RegistrationMetric::kGeneralized;
  p.voxel_m = 0.0;
  p.max_correspondence_m = 0.4;
  p.max_iterations = 30;
  return p;
}

void LidarReferenceParams::validate() const {
  clusters.validate();
  ego.validate();
  object.validate();
  if (!(association_gate_m > 0.0)) throw std::invalid_argument("lidar check association_gate_m must be positive");
  if (speed_window_frames < 1) throw std::invalid_argument("lidar check speed_window_frames must be >= 1");
  if (!(frame_interval_s > 0.0)) throw std::invalid_argument("lidar check frame_interval_s must be positive");
}

LidarReferenceBuilder::LidarReferenceBuilder(const LidarReferenceParams& params, const PinholeCamera& camera)
    : params_(params), camera_(camera) {
  params_.validate();
}

void LidarReferenceBuilder::add(const std::vector<Eigen::Vector3f>& points_camera,
                                const Eigen::Vector3f& lidar_origin_camera, const Eigen::Vector3f& lidar_up_camera) {
  const int frame = static_cast<int>(reference_.T_world_camera.size());
  const LidarMaskResult masks =
      LidarInstanceMask(points_camera, lidar_origin_camera, lidar_up_camera, camera_, params_.clusters);
  const LidarSegmentation& seg = masks.segmentation;

  // Static points: the structure above the ground outside every object-sized cluster, anywhere in the
  // scan, not only in the camera's view (a car beside the ego car, moving with it, would pull the
  // ego-motion towards its own). Not the ground: a spinning LiDAR's rings on flat ground stay at the same
  // range from the sensor as it moves, and registering them pulls the motion towards zero. Parked cars and
  // pillars are left out with the moving objects; so is a wall that shadows cut into object-sized pieces
  // (what a check of each cluster's own motion could win back: with dense traffic moving together, a
  // consensus over clusters took the traffic for the world).
  const LidarSegmentation whole = SegmentLidarObjects(points_camera, params_.clusters.segmentation);
  const float above_ground_m = static_cast<float>(params_.clusters.segmentation.ground_distance_m) + 0.1f;
  std::vector<bool> on_object(points_camera.size(), false);
  for (const LidarSegmentation* s : {&seg, &whole})
    for (const LidarObjectCluster& c : s->objects)
      for (int i : c.point_indices) on_object[i] = true;
  std::vector<Eigen::Vector3f> static_points;
  for (size_t i = 0; i < points_camera.size(); ++i) {
    const Eigen::Vector3f& p = points_camera[i];
    if (!on_object[i] && p.allFinite() && p.norm() < 60.0f && whole.heightAboveGround(p) > above_ground_m)
      static_points.push_back(p);
  }

  Eigen::Isometry3d T_prev_curr = Eigen::Isometry3d::Identity();
  if (frame == 0) {
    reference_.T_world_camera.push_back(SE3::Identity());
    reference_.ego_rms_m.push_back(0.0);
    reference_.ego_step_disagreement_m.push_back(0.0);
  } else {
    // Start from the previous step (constant velocity): stop-and-go traffic changes speed slowly.
    Eigen::Isometry3d guess = Eigen::Isometry3d::Identity();
    if (frame >= 2) {
      const SE3 step = reference_.T_world_camera[frame - 2].inverse() * reference_.T_world_camera[frame - 1];
      guess.linear() = step.rotationMatrix();
      guess.translation() = step.translation();
    }
    if (static_points.size() < 3 || previous_static_.size() < 3)
      throw std::runtime_error("LiDAR scan " + std::to_string(frame) + " or the one before has no static structure to register (" +
                               std::to_string(static_points.size()) + " and " + std::to_string(previous_static_.size()) +
                               " points above the ground outside the object clusters)");
    const Registration r = RegisterPoints(static_points, previous_static_, guess, params_.ego);
    T_prev_curr = r.T_target_source;
    reference_.T_world_camera.push_back(reference_.T_world_camera.back() * ToSE3(T_prev_curr));
    reference_.ego_rms_m.push_back(r.rms_m);
    // The same pair the other way round, from the same prior guess: how far the two disagree is the
    // reference's own step noise, the floor under any frame-to-frame comparison with it.
    const Registration back = RegisterPoints(previous_static_, static_points, guess.inverse(), params_.ego);
    reference_.ego_step_disagreement_m.push_back((T_prev_curr * back.T_target_source).translation().norm());
  }
  const SE3 T_world_curr = reference_.T_world_camera.back();
  const Eigen::Isometry3d T_curr_prev = T_prev_curr.inverse();

  // Clusters: each current cluster takes the nearest previous one (moved into this frame by the
  // ego-motion) within the gate, each previous cluster at most once, nearest pairs first.
  std::vector<int> whole_cluster_of(points_camera.size(), -1);
  for (size_t w = 0; w < whole.objects.size(); ++w)
    for (int i : whole.objects[w].point_indices) whole_cluster_of[i] = static_cast<int>(w);
  std::vector<Cluster> clusters(seg.objects.size());
  for (size_t c = 0; c < seg.objects.size(); ++c) {
    std::map<int, int> shared;  // whole-scan cluster -> points it shares with this one
    for (int i : seg.objects[c].point_indices)
      if (whole_cluster_of[i] >= 0) ++shared[whole_cluster_of[i]];
    clusters[c].centroid = seg.objects[c].centroid_camera;
    const auto most = std::max_element(shared.begin(), shared.end(),
                                       [](const auto& a, const auto& b) { return a.second < b.second; });
    const LidarObjectCluster& moving = most == shared.end() ? seg.objects[c] : whole.objects[most->first];
    for (int i : moving.point_indices) clusters[c].motion_points.push_back(points_camera[i]);
    clusters[c].motion_centroid = moving.centroid_camera;
  }
  std::vector<std::tuple<float, size_t, size_t>> pairs;  // distance, current, previous
  for (size_t c = 0; c < clusters.size(); ++c)
    for (size_t p = 0; p < previous_clusters_.size(); ++p) {
      const Eigen::Vector3f prev_here = (T_curr_prev.cast<float>() * previous_clusters_[p].centroid);
      const float d = (prev_here - clusters[c].centroid).norm();
      if (d < params_.association_gate_m) pairs.emplace_back(d, c, p);
    }
  std::sort(pairs.begin(), pairs.end());
  std::vector<int> match(clusters.size(), -1);
  std::vector<bool> taken(previous_clusters_.size(), false);
  for (const auto& [d, c, p] : pairs)
    if (match[c] < 0 && !taken[p]) match[c] = static_cast<int>(p), taken[p] = true;

  for (size_t c = 0; c < clusters.size(); ++c) {
    Cluster& cluster = clusters[c];
    LidarTrackSample s;
    s.frame = frame;
    s.centroid_camera = cluster.centroid.cast<double>();
    s.points = static_cast<int>(seg.objects[c].point_indices.size());
    s.extent_m = seg.objects[c].footprintDiagonal();
    s.box = masks.boxes[c];
    if (match[c] >= 0) {
      const Cluster& prev = previous_clusters_[static_cast<size_t>(match[c])];
      cluster.track_id = prev.track_id;
      const Vec3 moved = ObjectDisplacement(prev, cluster.motion_points, cluster.motion_centroid, T_curr_prev);
      s.velocity_world_mps = T_world_curr.rotationMatrix() * moved / params_.frame_interval_s;
      s.has_speed = true;
    } else {
      cluster.track_id = next_track_id_++;
    }
    s.track_id = cluster.track_id;
    reference_.samples.push_back(s);
  }
  previous_clusters_ = std::move(clusters);
  previous_static_ = std::move(static_points);
}

Vec3 LidarReferenceBuilder::ObjectDisplacement(const Cluster& previous, const std::vector<Eigen::Vector3f>& points,
                                              const Eigen::Vector3f& centroid, const Eigen::Isometry3d& T_curr_prev) const {
  // The object's own motion in this frame: its previous points, moved here by the ego-motion, onto its
  // current points, started from the centroids' offset; what it does to the point at the previous centroid.
  std::vector<Eigen::Vector3f> prev_here;
  prev_here.reserve(previous.motion_points.size());
  for (const Eigen::Vector3f& p : previous.motion_points) prev_here.push_back(T_curr_prev.cast<float>() * p);
  const Eigen::Vector3f c_prev = T_curr_prev.cast<float>() * previous.motion_centroid;
  Eigen::Isometry3d guess = Eigen::Isometry3d::Identity();
  guess.translation() = (centroid - c_prev).cast<double>();
  const Registration r = RegisterPoints(prev_here, points, guess, params_.object);
  return r.T_target_source * c_prev.cast<double>() - c_prev.cast<double>();
}

LidarReference LidarReferenceBuilder::finish() {
  // Windowed speeds: the mean velocity over the track's scans within the centred window.
  std::map<int, std::map<int, size_t>> by_track;  // track -> frame -> sample
  for (size_t i = 0; i < reference_.samples.size(); ++i)
    by_track[reference_.samples[i].track_id][reference_.samples[i].frame] = i;
  const int half = params_.speed_window_frames / 2;
  for (auto& [track, frames] : by_track)
    for (auto& [frame, i] : frames) {
      LidarTrackSample& s = reference_.samples[i];
      if (!s.has_speed) continue;
      Vec3 sum = Vec3::Zero();
      int n = 0;
      for (int f = frame - half; f <= frame + half; ++f) {
        const auto it = frames.find(f);
        if (it == frames.end() || !reference_.samples[it->second].has_speed) continue;
        sum += reference_.samples[it->second].velocity_world_mps;
        ++n;
      }
      s.speed_mps = (sum / n).norm();
    }
  return reference_;
}

}  // namespace dslam
