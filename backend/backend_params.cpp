#include "backend/backend_params.h"

#include <cmath>
#include <stdexcept>

namespace dslam {
namespace {
void RequirePositive(double value, const std::string& name) {
  if (!(value > 0.0) || !std::isfinite(value))
    throw std::invalid_argument(name + " must be a positive finite number, got " + std::to_string(value));
}
void RequireNonNegative(double value, const std::string& name) {
  if (!(value >= 0.0) || !std::isfinite(value))
    throw std::invalid_argument(name + " must be 0 or a positive finite number, got " + std::to_string(value));
}
}  // namespace

MotionMode BackendParams::modeFor(int object_id) const {
  const auto it = mode_per_object.find(object_id);
  return it == mode_per_object.end() ? default_mode : it->second;
}

void BackendParams::validate() const {
  RequirePositive(noise.point_sigma_m, "noise.point_sigma_m");
  RequireNonNegative(noise.point_sigma_per_depth_sq, "noise.point_sigma_per_depth_sq");
  RequirePositive(noise.motion_sigma_m, "noise.motion_sigma_m");
  RequirePositive(noise.smoothness_sigma_t_m, "noise.smoothness_sigma_t_m");
  RequirePositive(noise.smoothness_sigma_r_rad, "noise.smoothness_sigma_r_rad");
  RequirePositive(noise.prior_sigma, "noise.prior_sigma");
  RequirePositive(noise.huber_delta, "noise.huber_delta");
  RequireNonNegative(noise.smoothness_huber_delta, "noise.smoothness_huber_delta");  // 0: no kernel
  if (schedule.kind == ScheduleKind::kSlidingWindow && schedule.window_frames < 2)
    throw std::invalid_argument("schedule window W must be at least 2, got " + std::to_string(schedule.window_frames));
  if (motion_ransac.max_iterations < 1) throw std::invalid_argument("motion_ransac.max_iterations must be >= 1");
  RequirePositive(motion_ransac.inlier_threshold_m, "motion_ransac.inlier_threshold_m");
  if (motion_ransac.min_inliers < 3) throw std::invalid_argument("motion_ransac.min_inliers must be >= 3");
  if (object_window_frames < 2) throw std::invalid_argument("object_window_frames must be >= 2");
  if (landmark_history_frames < 0 || landmark_history_frames > 1000)
    throw std::invalid_argument("landmark_history_frames must be in [0, 1000]");
  if (max_iterations_batch < 1 || max_iterations_window < 1)
    throw std::invalid_argument("max_iterations_batch and max_iterations_window must be >= 1");
  RequirePositive(window_function_tolerance, "window_function_tolerance");
  RequirePositive(batch_function_tolerance, "batch_function_tolerance");
  if (num_threads < 1) throw std::invalid_argument("num_threads must be >= 1");
}

MotionMode ParseMotionMode(const std::string& text) {
  if (text == "per-step") return MotionMode::kPerStep;
  if (text == "constant") return MotionMode::kConstant;
  if (text == "smoothed") return MotionMode::kSmoothed;
  throw std::invalid_argument("unknown motion mode '" + text + "' (expected per-step, constant or smoothed)");
}

std::string ToString(MotionMode mode) {
  switch (mode) {
    case MotionMode::kPerStep: return "per-step";
    case MotionMode::kConstant: return "constant";
    case MotionMode::kSmoothed: return "smoothed";
  }
  return "?";
}

Schedule ParseSchedule(const std::string& text) {
  Schedule schedule;
  if (text == "batch") return schedule;
  const std::string prefix = "window:";
  if (text.rfind(prefix, 0) != 0)
    throw std::invalid_argument("unknown schedule '" + text + "' (expected batch or window:W)");
  const std::string number = text.substr(prefix.size());
  size_t used = 0;
  int w = 0;
  try {
    w = std::stoi(number, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != number.size())
    throw std::invalid_argument("schedule '" + text + "': W must be an integer");
  if (w < 2) throw std::invalid_argument("schedule '" + text + "': W must be at least 2");
  schedule.kind = ScheduleKind::kSlidingWindow;
  schedule.window_frames = w;
  return schedule;
}
Marginalisation ParseMarginalisation(const std::string& text) {
  if (text == "sparsified") return Marginalisation::kSparsified;
  if (text == "exact") return Marginalisation::kExact;
  throw std::invalid_argument("unknown marginalisation '" + text + "' (expected sparsified or exact)");
}

std::string ToString(Marginalisation marginalisation) {
  return marginalisation == Marginalisation::kExact ? "exact" : "sparsified";
}

LinearSolver ParseLinearSolver(const std::string& text) {
  if (text == "cholesky") return LinearSolver::kCholesky;
  if (text == "schur") return LinearSolver::kSchur;
  throw std::invalid_argument("unknown linear solver '" + text + "' (expected cholesky or schur)");
}

std::string ToString(LinearSolver solver) { return solver == LinearSolver::kSchur ? "schur" : "cholesky"; }

std::string ToString(const Schedule& schedule) {
  return schedule.kind == ScheduleKind::kBatch ? "batch" : "window:" + std::to_string(schedule.window_frames);
}

}  // namespace dslam
