#include "frontend/dynamic_object_classifier.h"

#include <stdexcept>
#include <unordered_map>

#include "geometry/velocity.h"

namespace dslam {
namespace {
// Pairs of the same track ids in two observation lists.
void MatchTracks(const std::vector<PointObservation>& prev, const std::vector<PointObservation>& curr,
                 std::vector<Vec3>* prev_pts, std::vector<Vec3>* curr_pts) {
  std::unordered_map<int64_t, const Vec3*> by_id;
  for (const auto& p : prev) by_id[p.track_id] = &p.p_camera;
  for (const auto& c : curr) {
    const auto it = by_id.find(c.track_id);
    if (it == by_id.end()) continue;
    prev_pts->push_back(*it->second);
    curr_pts->push_back(c.p_camera);
  }
}
}  // namespace

void ClassifierParams::validate() const {
  if (!(dynamic_speed_threshold_mps > 0.0))
    throw std::invalid_argument("classifier.dynamic_speed_threshold_mps must be positive");
  if (min_static_inliers < 3) throw std::invalid_argument("classifier.min_static_inliers must be >= 3");
}

DynamicObjectClassifier::DynamicObjectClassifier(const ClassifierParams& params, double frame_rate_hz)
    : params_(params), frame_rate_hz_(frame_rate_hz) {
  params_.validate();
}

SE3 DynamicObjectClassifier::cameraMotion(const FrameMeasurement& prev, const FrameMeasurement& curr) const {
  std::vector<Vec3> prev_pts, curr_pts;
  MatchTracks(prev.static_points, curr.static_points, &prev_pts, &curr_pts);
  if (static_cast<int>(prev_pts.size()) >= params_.min_static_inliers) {
    // z_prev = T_prev_curr * z_curr for static points.
    const auto fit = AlignRigidRansac(curr_pts, prev_pts, params_.static_ransac);
    if (fit && fit->num_inliers >= params_.min_static_inliers) return fit->transform;
  }
  return curr.odometry ? curr.odometry->T_prev_curr : SE3::Identity();
}

double DynamicObjectClassifier::objectSpeedMps(const ObjectObservation& prev, const ObjectObservation& curr,
                                               const SE3& T_prev_curr) const {
  std::vector<Vec3> prev_pts, curr_pts;
  MatchTracks(prev.points, curr.points, &prev_pts, &curr_pts);
  for (auto& p : curr_pts) p = T_prev_curr * p;  // into camera k-1: what remains is the object's own motion
  const auto fit = AlignRigidRansac(prev_pts, curr_pts, params_.object_ransac);
  if (!fit) return -1.0;
  Vec3 centroid = Vec3::Zero();
  for (size_t i = 0; i < prev_pts.size(); ++i)
    if (fit->is_inlier[i]) centroid += prev_pts[i];
  centroid /= static_cast<double>(fit->num_inliers);
  return SpeedMps(ObjectVelocityPerFrame(fit->transform, centroid), frame_rate_hz_);
}

void DynamicObjectClassifier::label(const FrameMeasurement& prev, FrameMeasurement* curr) const {
  const SE3 T_prev_curr = cameraMotion(prev, *curr);
  for (auto& obj : curr->objects) {
    obj.is_dynamic = true;
    for (const auto& before : prev.objects) {
      if (before.object_id != obj.object_id) continue;
      const double speed = objectSpeedMps(before, obj, T_prev_curr);
      if (speed >= 0.0) obj.is_dynamic = speed >= params_.dynamic_speed_threshold_mps;
    }
  }
}

}  // namespace dslam

namespace dslam {
void LabelDynamicObjects(const ClassifierParams& params, double frame_rate_hz, std::vector<FrameMeasurement>* frames) {
  const DynamicObjectClassifier classifier(params, frame_rate_hz);
  for (size_t k = 1; k < frames->size(); ++k) classifier.label((*frames)[k - 1], &(*frames)[k]);
}
}  // namespace dslam
