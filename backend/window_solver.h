#pragma once
// The fixed-lag smoother's solver: Levenberg-Marquardt over the factors of frames [first_frame,
// last_frame] of a FactorGraph, solved in place, with the problem's structure exploited by hand.
//
// Why not Ceres here: profiled on bench_window_solve, 44 % of a Ceres window solve was Eigen's scalar
// simplicial LDLT (CHOLMOD with the system's BLAS was slower still) and the rest building the problem
// again every frame. The structure is simple enough to eliminate directly:
//  - point variables form small groups: a static landmark alone, or an object point's per-frame
//    variables chained by the ternary factor (as long as the smoother's object window);
//  - each group is eliminated densely (a few 3x3 blocks) into a Schur complement over the pose-like
//    blocks it touches (cameras and object motions), analytic Jacobians throughout;
//  - what remains, the window's cameras and motions (a few hundred dimensions), is solved densely.
// The camera before first_frame, when stored, is held constant (its odometry factor anchors the window),
// unless FactorGraph::camera_prior is on the first camera (BackendParams::camera_prior_by_schur): then
// the odometry into it was eliminated with the cameras that left, and that prior anchors the window.

#include <vector>

#include "backend/backend_params.h"
#include "backend/factor_graph.h"

namespace dslam {

struct WindowSolveOptions {
  int first_frame = 0;
  int last_frame = 0;
  int max_iterations = 10;
  // Stop when the cost falls by less than this fraction, or when the next decrease, predicted from the last
  // two (d_next = d^2 / d_previous: a converging Gauss-Newton's decreases shrink at least linearly), would.
  double function_tolerance = 1e-3;
  bool fix_cameras = false;          // SLAM+MOT's object stage: camera poses come from the static stage
  // After the solve, each motion's marginal covariance (MotionVariable::covariance) from the window's
  // information, read from the last step's factorisation (no extra linearisation).
  bool motion_covariance = true;
  // After the solve, the covariance of each camera step whose two cameras are in the window
  // (WindowSolveSummary::camera_step_covariances), from the same factorisation.
  bool camera_step_covariance = false;
  // Take no step: only the covariances at the current estimate (the batch schedule's, after its own
  // solve).
  bool covariance_only = false;
};

// The covariance of camera k's step T[k-1]^-1 T[k], over its tangent [translation, in camera k-1;
// rotation, perturbed on the right], with every other variable of the window marginalised.
struct CameraStepCovariance {
  int frame = 0;  // k
  Mat6 covariance = Mat6::Zero();
};

struct WindowSolveSummary {
  int num_residual_blocks = 0;
  int num_iterations = 0;
  double initial_cost = 0.0;
  double final_cost = 0.0;
  std::vector<double> relative_decreases;  // of each accepted step, in order
  std::vector<CameraStepCovariance> camera_step_covariances;  // in frame order
};

WindowSolveSummary SolveWindow(const BackendParams& params, const WindowSolveOptions& options, FactorGraph* graph);

}  // namespace dslam
