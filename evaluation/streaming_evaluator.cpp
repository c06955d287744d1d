#include "evaluation/streaming_evaluator.h"

#include <stdexcept>
#include <utility>

namespace dslam {

StreamingEvaluator::StreamingEvaluator(const GroundTruth& gt, double frame_rate_hz, bool estimates_objects,
                                       std::string category)
    : gt_(gt), frame_rate_hz_(frame_rate_hz), estimates_objects_(estimates_objects), category_(std::move(category)) {
  T_world_camera_est_.reserve(gt.T_world_camera.size());
}

void StreamingEvaluator::frameMade(int frame) {
  if (frame != frames_made_)
    throw std::logic_error("evaluation: frame " + std::to_string(frame) + " made after frame " +
                           std::to_string(frames_made_ - 1));
  ++frames_made_;
  if (!estimates_objects_) return;
  // Every ground-truth pair ending here, measured or not (as EvaluateEstimate counts them).
  for (const auto& [id, obj] : gt_.objects) {
    if (!obj.observed_frames.count(frame)) continue;
    const std::optional<ObjectPairSample> pair = GroundTruthPair(gt_, frame_rate_hz_, id, frame);
    if (!pair) continue;
    summaries_.addPair(*pair, obj.category);
    if (category_.empty() || obj.category == category_) objects_.addPair(*pair);
  }
}

void StreamingEvaluator::cameraFinal(int frame, const SE3& T_world_camera) {
  if (frame != static_cast<int>(T_world_camera_est_.size()) || frame >= static_cast<int>(gt_.T_world_camera.size()))
    throw std::logic_error("evaluation: camera " + std::to_string(frame) + " final out of order");
  T_world_camera_est_.push_back(T_world_camera);
  const bool has_step_covariance = step_covariance_ && step_covariance_->first == frame;
  camera_.add(gt_.T_world_camera[frame], T_world_camera, has_step_covariance ? &step_covariance_->second : nullptr);
  step_covariance_.reset();
  const auto [first, last] = waiting_.equal_range(frame);
  for (auto it = first; it != last; ++it) addPoint(it->second);
  waiting_.erase(first, last);
}

void StreamingEvaluator::cameraStepCovariance(int frame, const Mat6& covariance) {
  step_covariance_.emplace(frame, covariance);
}

void StreamingEvaluator::pointFinal(const PointEstimate& point) {
  if (point.frame < static_cast<int>(T_world_camera_est_.size()))
    addPoint(point);  // SLAM+MOT's object stage runs behind its cameras
  else
    waiting_.emplace(point.frame, point);
}

void StreamingEvaluator::addPoint(const PointEstimate& p) {
  Vec3 p_gt_world;
  if (!gt_.pointWorld(p.track_id, p.frame, &p_gt_world)) return;
  structure_.add(T_world_camera_est_[p.frame].inverse() * p.p_world,
                 gt_.T_world_camera[p.frame].inverse() * p_gt_world);
}

void StreamingEvaluator::motionFinal(const ObjectMotionEstimate& motion) {
  if (!estimates_objects_) return;
  const std::optional<int> gt_id = GroundTruthIdOf(gt_, motion.object_id, motion.frame);
  if (!gt_id) return;
  std::optional<ObjectPairSample> sample = GroundTruthPair(gt_, frame_rate_hz_, *gt_id, motion.frame);
  if (!sample) return;
  SetEstimate(motion, &*sample);
  summaries_.addEstimate(*sample);
  if (category_.empty() || gt_.objects.at(*gt_id).category == category_) objects_.addEstimate(*sample);
}

MethodMetrics StreamingEvaluator::metrics() const {
  if (camera_.poses() != frames_made_)
    throw std::logic_error("evaluation: " + std::to_string(camera_.poses()) + " final cameras for " +
                           std::to_string(frames_made_) + " frames");
  if (!waiting_.empty())
    throw std::logic_error("evaluation: a point of frame " + std::to_string(waiting_.begin()->first) +
                           " has no final camera");
  MethodMetrics m;
  m.camera = camera_.result();
  m.rse_pct = structure_.result();
  if (estimates_objects_) m.objects = objects_.result();
  return m;
}

}  // namespace dslam
