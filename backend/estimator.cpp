#include "backend/estimator.h"

#include <algorithm>
#include <chrono>
#include <map>
#include <stdexcept>

#include "backend/exact_marginalisation.h"
#include "backend/factors/pose_block.h"
#include "backend/graph_solver.h"
#include "backend/marginalisation.h"
#include "backend/process_noise.h"
#include "backend/window_solver.h"

namespace dslam {

Estimator::Estimator(const BackendParams& params, double frame_rate_hz, const EstimatorOptions& options)
    : params_(params),
      frame_rate_hz_(frame_rate_hz),
      options_(options),
      builder_(params_, options.builder, &graph_),
      sink_(options.sink ? options.sink : &collected_) {
  params_.validate();
  if (!(frame_rate_hz > 0.0)) throw std::invalid_argument("frame rate must be positive");
}

void Estimator::addFrame(const FrameMeasurement& frame) {
  const int k = graph_.numFrames();
  SE3 fixed;
  if (options_.fixed_T_world_camera) fixed = options_.fixed_T_world_camera(k);
  builder_.addFrame(frame, options_.fixed_T_world_camera ? &fixed : nullptr);
  if (params_.schedule.kind != ScheduleKind::kSlidingWindow) return;

  const auto start = std::chrono::steady_clock::now();
  const SolveStats stats = params_.marginalisation == Marginalisation::kExact ? stepExact(k) : stepSparsified(k);
  recordSolve(stats, start);
}

// The sparsified window: what leaves is marginalised by type (backend/marginalisation.h) and the window is
// solved by its own solver (backend/window_solver.h).
Estimator::SolveStats Estimator::stepSparsified(int k) {
  const int window = params_.schedule.window_frames;
  const int object_window = std::min(params_.object_window_frames, window);
  if (object_window == window) {
    if (k - window >= 0) MarginaliseObjectFrame(params_, frame_rate_hz_, k - window, &graph_, sink_);
  } else {
    if (k - object_window >= 0)
      MarginaliseObjectFrame(params_, frame_rate_hz_, k - object_window, &graph_, sink_, ObjectWindow::kPerFrameMotion);
    if (k - window >= 0)
      MarginaliseObjectFrame(params_, frame_rate_hz_, k - window, &graph_, sink_, ObjectWindow::kTrackMotion);
  }
  if (k - window >= 0) {
    handStepCovariance(k - window);
    MarginaliseCameraFrame(params_, k - window, &graph_, sink_);
    cameras_final_ = k - window + 1;
  }
  WindowSolveOptions solve;
  solve.first_frame = std::max(0, k - window + 1);
  solve.last_frame = k;
  solve.max_iterations = params_.max_iterations_window;
  solve.function_tolerance = params_.window_function_tolerance;
  solve.fix_cameras = static_cast<bool>(options_.fixed_T_world_camera);
  solve.camera_step_covariance = !solve.fix_cameras;
  // Before the solve, so that the newest motions (their own points' fit) are judged before they pull.
  UpdateSmoothnessScales(params_, solve.first_frame, solve.last_frame, &graph_);
  const WindowSolveSummary summary = SolveWindow(params_, solve, &graph_);
  for (const CameraStepCovariance& c : summary.camera_step_covariances) camera_step_covariance_[c.frame] = c.covariance;
  return {summary.num_residual_blocks, summary.num_iterations};
}

// The exact fixed lag: the leaving frame is eliminated into the dense prior, and the window, prior
// included, is solved by Ceres (backend/exact_marginalisation.h). One window of W frames for every
// variable.
Estimator::SolveStats Estimator::stepExact(int k) {
  const int window = params_.schedule.window_frames;
  const bool fix_cameras = static_cast<bool>(options_.fixed_T_world_camera);
  if (k - window >= 0) {
    MarginaliseFrameExactly(params_, frame_rate_hz_, k - window, fix_cameras, &graph_, sink_);
    cameras_final_ = k - window + 1;
  }
  SolveOptions solve;
  solve.first_frame = std::max(0, k - window + 1);
  solve.last_frame = k;
  solve.max_iterations = params_.max_iterations_window;
  solve.function_tolerance = params_.window_function_tolerance;
  solve.num_threads = params_.num_threads;
  solve.fix_cameras = fix_cameras;
  UpdateSmoothnessScales(params_, solve.first_frame, solve.last_frame, &graph_);
  const SolveSummary summary = SolveGraph(params_, solve, &graph_);
  return {summary.num_residual_blocks, summary.num_iterations};
}

void Estimator::recordSolve(const SolveStats& stats, std::chrono::steady_clock::time_point start) {
  if (!options_.keep_solve_history) {
    solve_residual_blocks_.clear();
    solve_iterations_.clear();
    solve_times_ms_.clear();
  }
  solve_residual_blocks_.push_back(stats.residual_blocks);
  solve_iterations_.push_back(stats.iterations);
  solve_times_ms_.push_back(
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
}

// Batch: re-solves with each object's smoothness scales from the last solve's residuals until no scale
// changes by more than kProcessNoiseSettled (relative), at most kMaxProcessNoiseRounds times.
constexpr int kMaxProcessNoiseRounds = 3;
constexpr double kProcessNoiseSettled = 0.05;

Estimate Estimator::finish() {
  if (params_.schedule.kind == ScheduleKind::kBatch) {
    SolveOptions solve;
    solve.last_frame = graph_.numFrames() - 1;
    solve.max_iterations = params_.max_iterations_batch;
    solve.function_tolerance = params_.batch_function_tolerance;
    solve.num_threads = params_.num_threads;
    solve.fix_cameras = static_cast<bool>(options_.fixed_T_world_camera);
    SolveGraph(params_, solve, &graph_);
    // Each object's process noise from its residuals, solved again until the scales settle.
    for (int round = 0; round < kMaxProcessNoiseRounds &&
                        UpdateSmoothnessScales(params_, 0, solve.last_frame, &graph_) > kProcessNoiseSettled;
         ++round)
      SolveGraph(params_, solve, &graph_);
    batchCovariances();
  }
  flush();
  return std::move(collected_.estimate);
}

// Frames on each side of a motion (a camera step) whose information gives its covariance in a batch run;
// the rest of the trajectory is held. The whole trajectory's dense system would not fit a long run, and
// farther frames barely inform one motion. Held frames inform nothing, so the sigma errs on the wide side.
constexpr int kBatchCovarianceHalfWindow = 5;

void Estimator::batchCovariances() {
  std::map<int, std::vector<int>> motions_by_frame;
  for (const auto& [id, motion] : graph_.motions) motions_by_frame[motion.first_frame].push_back(id);
  const bool fix_cameras = static_cast<bool>(options_.fixed_T_world_camera);
  std::map<int, Mat6> covariances;
  const int last = graph_.numFrames() - 1;
  for (int frame = 0; frame <= last; ++frame) {
    const auto motions = motions_by_frame.find(frame);
    const bool camera_step = frame > 0 && !fix_cameras;
    if (motions == motions_by_frame.end() && !camera_step) continue;
    WindowSolveOptions window;
    window.first_frame = std::max(0, frame - kBatchCovarianceHalfWindow);
    window.last_frame = std::min(last, frame + kBatchCovarianceHalfWindow);
    window.fix_cameras = fix_cameras;
    window.camera_step_covariance = camera_step;
    window.covariance_only = true;
    static const std::vector<int> kNoMotions;
    const std::vector<int>& ids = motions == motions_by_frame.end() ? kNoMotions : motions->second;
    for (int id : ids) graph_.motions.at(id).covariance.setZero();
    const WindowSolveSummary summary = SolveWindow(params_, window, &graph_);
    for (int id : ids) covariances[id] = graph_.motions.at(id).covariance;  // later windows overwrite the graph's
    for (const CameraStepCovariance& c : summary.camera_step_covariances)
      if (c.frame == frame) camera_step_covariance_[frame] = c.covariance;
  }
  for (const auto& [id, covariance] : covariances) graph_.motions.at(id).covariance = covariance;
}

void Estimator::handStepCovariance(int frame) {
  const auto it = camera_step_covariance_.find(frame);
  if (it == camera_step_covariance_.end()) return;
  sink_->cameraStepCovariance(frame, it->second);
  camera_step_covariance_.erase(camera_step_covariance_.begin(), std::next(it));
}

void Estimator::flush() {
  for (const auto& tr : graph_.transitions)
    if (tr.reportable()) sink_->motionFinal(MotionEstimateOf(graph_, tr, frame_rate_hz_));
  graph_.transitions.clear();
  for (int k = cameras_final_; k < graph_.numFrames(); ++k) {
    for (const auto& meas : graph_.frame(k).measurements) {
      const PointVariable& var = graph_.points.at(meas.point_var);
      sink_->pointFinal({k, var.track_id, var.object_id, var.position()});
    }
  }
  for (; cameras_final_ < graph_.numFrames(); ++cameras_final_) {
    handStepCovariance(cameras_final_);
    sink_->cameraFinal(cameras_final_, BlockToPose(graph_.camera(cameras_final_)));
  }
}

FrameEstimate Estimator::latest() const {
  FrameEstimate out;
  if (graph_.numFrames() == 0) return out;
  out.frame = graph_.numFrames() - 1;
  out.T_world_camera = BlockToPose(graph_.camera(out.frame));
  // Transitions are appended frame by frame: the newest frame's are at the back.
  for (auto it = graph_.transitions.rbegin(); it != graph_.transitions.rend() && it->frame == out.frame; ++it) {
    if (!it->reportable()) continue;
    out.object_motions.push_back(MotionEstimateOf(graph_, *it, frame_rate_hz_));
  }
  std::reverse(out.object_motions.begin(), out.object_motions.end());
  return out;
}

}  // namespace dslam
