#include "backend/methods.h"

#include <chrono>
#include <stdexcept>

#include "backend/estimator.h"

namespace dslam {
namespace {
Estimate RunEstimator(const BackendParams& params, double frame_rate_hz, const std::vector<FrameMeasurement>& frames,
                      const EstimatorOptions& options, const ProgressCallback& progress, std::vector<double>* solve_ms,
                      std::vector<FrameEstimate>* online = nullptr) {
  Estimator estimator(params, frame_rate_hz, options);
  for (size_t k = 0; k < frames.size(); ++k) {
    estimator.addFrame(frames[k]);
    if (online) {
      online->push_back(estimator.latest());
      online->back().t_ns = frames[k].t_ns;
    }
    if (progress) progress(static_cast<int>(k + 1), static_cast<int>(frames.size()));
  }
  Estimate est = estimator.finish();
  if (solve_ms) *solve_ms = estimator.solveTimesMs();
  return est;
}
}  // namespace

std::string ToString(Method method) {
  switch (method) {
    case Method::kOurs: return "ours";
    case Method::kStaticOnly: return "static_only";
    case Method::kSlamMot: return "slam_mot";
  }
  return "?";
}

MethodResult RunMethod(Method method, const BackendParams& params, double frame_rate_hz,
                       const std::vector<FrameMeasurement>& frames, const ProgressCallback& progress) {
  const auto start = std::chrono::steady_clock::now();
  MethodResult result;
  EstimatorOptions options;
  if (method == Method::kOurs) {
    result.estimate =
        RunEstimator(params, frame_rate_hz, frames, options, progress, &result.solve_times_ms, &result.online);
  } else {
    options.builder.use_objects = false;
    Estimate static_stage = RunEstimator(params, frame_rate_hz, frames, options, progress, &result.solve_times_ms);
    if (method == Method::kStaticOnly) {
      result.estimate = std::move(static_stage);
    } else {
      // Object stage: the object factors alone, cameras held at the static stage's estimate.
      EstimatorOptions object_stage;
      object_stage.builder.use_static_points = false;
      object_stage.builder.use_odometry = false;
      object_stage.fixed_T_world_camera = [&static_stage](int k) {
        if (k >= static_cast<int>(static_stage.T_world_camera.size()))
          throw std::invalid_argument("fixed camera trajectory is shorter than the sequence");
        return static_stage.T_world_camera[k];
      };
      BackendParams tracker = params;
      tracker.default_mode = params.slam_mot_mode;
      tracker.mode_per_object.clear();
      Estimate objects = RunEstimator(tracker, frame_rate_hz, frames, object_stage, {}, nullptr);
      result.estimate.T_world_camera = static_stage.T_world_camera;
      result.estimate.camera_step_covariance = std::move(static_stage.camera_step_covariance);  // the same cameras
      result.estimate.object_motions = std::move(objects.object_motions);
      result.estimate.points = std::move(static_stage.points);
      result.estimate.points.insert(result.estimate.points.end(), objects.points.begin(), objects.points.end());
    }
  }
  result.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace dslam
