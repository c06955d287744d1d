#pragma once
// Back-end configuration: plain structs with defaults; validate() throws std::invalid_argument
// with a message naming the offending field. YAML loading happens at the edge (app/).

#include <map>
#include <string>

#include "geometry/rigid_alignment.h"

namespace dslam {

enum class MotionMode {
  kPerStep,   // a new H vertex per object per frame transition
  kConstant,  // one H vertex per object for its whole track
  kSmoothed,  // per-step vertices tied by the smoothness factor
};

enum class ScheduleKind { kBatch, kSlidingWindow };

struct Schedule {
  ScheduleKind kind = ScheduleKind::kBatch;
  int window_frames = 10;  // W, for the sliding window
};

// How the sliding window lets a frame go (backend/marginalisation.h, backend/exact_marginalisation.h).
enum class Marginalisation {
  kSparsified,  // per variable type, cameras held: the graph's structure and the solver's cost unchanged
  kExact,       // one Schur complement into a dense prior, first-estimate Jacobians; solved by Ceres
};

// How the normal equations are solved; both eliminate the points before poses and motions.
enum class LinearSolver { kCholesky, kSchur };

struct NoiseParams {
  double point_sigma_m = 0.02;               // 3D measurement sigma per axis at zero depth
  double point_sigma_per_depth_sq = 0.0;     // added sigma per m^2 of depth, along the viewing ray (stereo / RGB-D)
  double motion_sigma_m = 0.005;             // ternary point-motion factor (rigidity)
  double smoothness_sigma_t_m = 0.1;         // smoothness factor, translation part
  double smoothness_sigma_r_rad = 0.02;      // smoothness factor, rotation part
  double prior_sigma = 1e-4;                 // prior on the first camera pose (m and rad)
  double huber_delta = 2.0;                  // Huber threshold on whitened residuals
  // Huber threshold on the smoothness factor's whitened 6-D residual; 0: plain least squares. An object
  // whose motion breaks the model (a hard brake, a box label that jitters) then reaches the cameras only
  // as far as its motion is explained.
  double smoothness_huber_delta = 0.0;
  // Each object's smoothness sigmas scaled by its own residuals, never below the configured ones
  // (backend/process_noise.h): a variance-component estimate of its process noise.
  bool smoothness_from_residuals = true;
};

struct BackendParams {
  NoiseParams noise;
  MotionMode default_mode = MotionMode::kPerStep;
  std::map<int, MotionMode> mode_per_object;  // overrides default_mode for listed object ids
  Schedule schedule;
  // Motion model of the SLAM+MOT baseline's tracker. A multi-object tracker estimates each object's
  // motion frame to frame; the constant and smoothed models belong to the joint method.
  MotionMode slam_mot_mode = MotionMode::kPerStep;
  RansacParams motion_ransac{200, 0.3, 4, 7};  // H initialisation and outlier-track rejection
  // Fixed-lag smoother: per-frame object points and object motions stay this many frames (2..W) in the
  // window; older ones are marginalised (backend/marginalisation.h). Cameras, static structure and the
  // points of objects with one motion for their whole track (constant mode) stay W. 4: with 3 the
  // objects' errors were 2.3 to 4.6 % above the Ceres window's on three acceptance scenes (docs/benchmarks.md,
  // "Back-end"); 5 cost another 40 % of the back-end's time for less than a point more.
  int object_window_frames = 4;
  // Window: frames of a landmark's measurements kept as robust factors after their camera left the
  // window (camera held), before they are folded into its prior.
  int landmark_history_frames = 30;
  // Window: a leaving camera is eliminated by a Schur complement into a prior on the next camera
  // (backend/marginalisation.h) instead of being held as the next window's anchor. Off: with the
  // landmarks' measurements still folded with their cameras held, the exact camera prior made the
  // simulated city's ATE 0.0180 m against 0.0161 held (batch 0.0140) and the paper scene's 0.705 against
  // 0.635 (batch 0.400), seed 1, window 10: the held landmark priors are overconfident, and only the
  // camera held at its estimate matches them. To turn on when the landmarks leave exactly too.
  bool camera_prior_by_schur = false;
  // Window: how a leaving frame's variables are eliminated. kExact keeps all their information (and its
  // correlations) in one dense prior and solves the window with Ceres over one window of W frames for
  // every variable (object_window_frames, landmark_history_frames and camera_prior_by_schur do not apply);
  // it costs 10 (paper scene) to 1,000 (simulated city) times the sparsified window's back-end time a frame
  // (docs/results.md, "The exact fixed lag").
  Marginalisation marginalisation = Marginalisation::kSparsified;
  int max_iterations_batch = 50;
  int max_iterations_window = 10;
  // Relative cost decrease below which a window solve stops. Each window starts from the previous
  // window's solution and every variable is solved again in each later solve it stays in, so a solve
  // need not converge on its own. What the iterations past 1e-3 still gain is mostly landmarks with
  // measurements beyond the Huber threshold creeping towards their optimum (reweighting converges
  // linearly there) while the poses move by under 0.1 mm: on the demo scene they were a third of the
  // back-end's time and changed no acceptance metric by more than 2 % (docs/benchmarks.md).
  double window_function_tolerance = 1e-3;
  // Relative cost decrease below which the batch solve stops. It must be small: a long run's cost is a
  // sum over many residuals, so 1e-6 of it still moved the camera path by centimetres (KITTI replay
  // 0005: ATE 0.048 m at 1e-6, 0.043 m converged), and one method could stop earlier than another.
  double batch_function_tolerance = 1e-8;
  int num_threads = 1;  // 1 keeps results bit-for-bit repeatable
  LinearSolver linear_solver = LinearSolver::kCholesky;

  MotionMode modeFor(int object_id) const;
  void validate() const;
};

// Parsing helpers shared by the CLI and the YAML loader; they throw std::invalid_argument.
MotionMode ParseMotionMode(const std::string& text);
std::string ToString(MotionMode mode);
// "batch" or "window:W".
Schedule ParseSchedule(const std::string& text);
std::string ToString(const Schedule& schedule);
Marginalisation ParseMarginalisation(const std::string& text);  // "sparsified" or "exact"
std::string ToString(Marginalisation marginalisation);
LinearSolver ParseLinearSolver(const std::string& text);  // "cholesky" or "schur"
std::string ToString(LinearSolver solver);

}  // namespace dslam
