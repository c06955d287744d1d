#pragma once
// The batch schedule: builds a Ceres problem from the factors of frames [first_frame, last_frame] and
// solves it in place. Variables only observed before first_frame are held constant; the prior on the
// first camera is included when the range starts at frame 0, and the graph's dense prior (the exact
// fixed-lag smoother's, backend/exact_marginalisation.h) whenever there is one. (The default online
// schedule is the sparsified fixed-lag smoother, backend/window_solver.h.)

#include "backend/backend_params.h"
#include "backend/factor_graph.h"

namespace dslam {

struct SolveOptions {
  int first_frame = 0;
  int last_frame = 0;
  int max_iterations = 50;
  int num_threads = 1;
  bool fix_cameras = false;  // SLAM+MOT's object stage: camera poses come from the static stage
  double function_tolerance = 1e-8;
  // Levenberg-Marquardt's first trust region, far larger than Ceres' 1e4. The problem is nearly quadratic
  // from the odometry's start, but the slow drift along a long path is weakly observed, and a damping of
  // 1e-4 of each diagonal entry shrank every step along it: the solve crept there for a dozen
  // iterations. From 1e8 the first steps are Gauss-Newton's; a step that fails shrinks the region as before.
  double initial_trust_region_radius = 1e8;
};

struct SolveSummary {
  int num_residual_blocks = 0;
  int num_iterations = 0;
  double initial_cost = 0.0;
  double final_cost = 0.0;
  bool usable = false;
};

SolveSummary SolveGraph(const BackendParams& params, const SolveOptions& options, FactorGraph* graph);

}  // namespace dslam
