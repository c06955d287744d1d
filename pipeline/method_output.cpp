#include "pipeline/method_output.h"

namespace dslam {

StreamedFiles FilesOf(Method method) {
  StreamedFiles files;
  files.method = ToString(method);
  files.kitti = true;
  files.online = files.map_points = method == Method::kOurs;
  files.object_tables = method != Method::kStaticOnly;
  if (method == Method::kSlamMot) files.object_suffix = "_slam_mot";
  return files;
}

MethodOutput::MethodOutput(Method method, const std::string& dir, const GroundTruth* gt, double frame_rate_hz,
                           const std::string& category) {
  if (gt) evaluator_.emplace(*gt, frame_rate_hz, method != Method::kStaticOnly, category);
  if (!dir.empty()) files_.emplace(dir, FilesOf(method), gt, frame_rate_hz);
}

void MethodOutput::frameMade(int frame, int64_t t_ns) {
  if (evaluator_) evaluator_->frameMade(frame);
  if (files_) files_->frameStamp(frame, t_ns);
}

void MethodOutput::onlinePose(int64_t t_ns, const SE3& T_world_camera) {
  if (files_) files_->onlinePose(t_ns, T_world_camera);
}

void MethodOutput::cameraFinal(int frame, const SE3& T_world_camera) {
  if (evaluator_) evaluator_->cameraFinal(frame, T_world_camera);
  if (files_) files_->cameraFinal(frame, T_world_camera);
}

void MethodOutput::motionFinal(const ObjectMotionEstimate& motion) {
  if (evaluator_) evaluator_->motionFinal(motion);
  if (files_) files_->motionFinal(motion);
}

void MethodOutput::pointFinal(const PointEstimate& point) {
  if (evaluator_) evaluator_->pointFinal(point);
  if (files_) files_->pointFinal(point);
}

void MethodOutput::cameraStepCovariance(int frame, const Mat6& covariance) {
  if (evaluator_) evaluator_->cameraStepCovariance(frame, covariance);
  if (files_) files_->cameraStepCovariance(frame, covariance);
}

void MethodOutput::finish() {
  if (files_) files_->finish();
}

MethodMetrics MethodOutput::metrics() const { return evaluator_ ? evaluator_->metrics() : MethodMetrics{}; }

std::vector<ObjectSummary> MethodOutput::objects() const {
  return evaluator_ ? evaluator_->objects() : std::vector<ObjectSummary>{};
}

MethodOutputs MakeMethodOutputs(const std::vector<Method>& methods, const std::string& dir, const GroundTruth* gt,
                                double frame_rate_hz, const std::string& category) {
  MethodOutputs outputs;
  for (Method method : methods)
    if (!outputs.count(method)) outputs[method] = std::make_unique<MethodOutput>(method, dir, gt, frame_rate_hz, category);
  return outputs;
}

MethodOutcomes FinishMethodOutputs(MethodOutputs& outputs, const std::function<double(Method)>& wall_time_s,
                                   std::vector<ObjectSummary>* ours_objects) {
  MethodOutcomes outcomes;
  for (auto& [method, output] : outputs) {
    output->finish();
    MethodOutcome& outcome = outcomes[method];
    outcome.metrics = output->metrics();
    outcome.result.wall_time_s = wall_time_s(method);
    if (method == Method::kOurs) *ours_objects = output->objects();
  }
  return outcomes;
}

}  // namespace dslam
