#include "backend/estimator.h"

#include <algorithm>

#include <chrono>
#include <stdexcept>

#include "backend/factors/pose_block.h"
#include "backend/graph_solver.h"
#include "geometry/velocity.h"

namespace dslam {

Estimator::Estimator(const BackendParams& params, double frame_rate_hz, const EstimatorOptions& options)
    : params_(params), frame_rate_hz_(frame_rate_hz), options_(options), builder_(params_, options.builder, &graph_) {
  params_.validate();
  if (!(frame_rate_hz > 0.0)) throw std::invalid_argument("frame rate must be positive");
}

void Estimator::addFrame(const FrameMeasurement& frame) {
  const int k = graph_.numFrames();
  const SE3* init = nullptr;
  if (options_.fixed_T_world_camera) {
    if (k >= static_cast<int>(options_.fixed_T_world_camera->size()))
      throw std::invalid_argument("fixed camera trajectory is shorter than the sequence");
    init = &(*options_.fixed_T_world_camera)[k];
  }
  builder_.addFrame(frame, init);
  if (params_.schedule.kind != ScheduleKind::kSlidingWindow) return;

  const auto start = std::chrono::steady_clock::now();
  SolveOptions solve = solveOptions(k - params_.schedule.window_frames + 1, k, params_.max_iterations_window);
  solve.function_tolerance = params_.window_function_tolerance;
  solve.history_frames = params_.window_history_frames;
  const SolveSummary summary = SolveGraph(params_, solve, &graph_);
  solve_residual_blocks_.push_back(summary.num_residual_blocks);
  solve_iterations_.push_back(summary.num_iterations);
  solve_times_ms_.push_back(
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
}

Estimate Estimator::finish() {
  if (params_.schedule.kind == ScheduleKind::kBatch)
    SolveGraph(params_, solveOptions(0, graph_.numFrames() - 1, params_.max_iterations_batch), &graph_);
  return extract();
}

SolveOptions Estimator::solveOptions(int first_frame, int last_frame, int max_iterations) const {
  SolveOptions solve;
  solve.first_frame = first_frame;
  solve.last_frame = last_frame;
  solve.max_iterations = max_iterations;
  solve.num_threads = params_.num_threads;
  solve.fix_cameras = options_.fixed_T_world_camera != nullptr;
  return solve;
}

ObjectMotionEstimate Estimator::motionEstimate(const ObjectTransition& tr) const {
  ObjectMotionEstimate m;
  m.object_id = tr.object_id;
  m.frame = tr.frame;
  m.is_dynamic = tr.is_dynamic;
  if (tr.is_dynamic) m.H_world = graph_.motions[tr.motion_var].worldMotion();
  Vec3 centroid = Vec3::Zero();
  for (int v : tr.prev_point_vars) {
    const auto& p = graph_.points[v].p_world;
    centroid += Vec3(p[0], p[1], p[2]);
  }
  if (!tr.prev_point_vars.empty()) centroid /= static_cast<double>(tr.prev_point_vars.size());
  m.centroid_prev_world = centroid;
  m.velocity_world_per_frame = tr.is_dynamic ? ObjectVelocityPerFrame(m.H_world, centroid) : Vec3::Zero();
  m.speed_mps = SpeedMps(m.velocity_world_per_frame, frame_rate_hz_);
  return m;
}

FrameEstimate Estimator::latest() const {
  FrameEstimate out;
  if (graph_.numFrames() == 0) return out;
  out.frame = graph_.numFrames() - 1;
  out.T_world_camera = BlockToPose(graph_.camera_poses.back().data());
  // Transitions are appended frame by frame: the newest frame's are at the back.
  for (auto it = graph_.transitions.rbegin(); it != graph_.transitions.rend() && it->frame == out.frame; ++it) {
    if (it->is_dynamic && it->motion_var < 0) continue;
    out.object_motions.push_back(motionEstimate(*it));
  }
  std::reverse(out.object_motions.begin(), out.object_motions.end());
  return out;
}

Estimate Estimator::extract() const {
  Estimate est;
  for (const auto& block : graph_.camera_poses) est.T_world_camera.push_back(BlockToPose(block.data()));
  for (const auto& tr : graph_.transitions) {
    if (tr.is_dynamic && tr.motion_var < 0) continue;  // no estimate for this transition
    est.object_motions.push_back(motionEstimate(tr));
  }
  for (int k = 0; k < graph_.numFrames(); ++k) {
    for (const auto& meas : graph_.frames[k].measurements) {
      const PointVariable& var = graph_.points[meas.point_var];
      est.points.push_back({k, var.track_id, var.object_id, Vec3(var.p_world[0], var.p_world[1], var.p_world[2])});
    }
  }
  return est;
}

}  // namespace dslam
