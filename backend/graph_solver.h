#pragma once
// The batch schedule: builds a Ceres problem from the factors of frames [first_frame, last_frame] and
// solves it in place. Variables only observed before first_frame are held constant; the prior on the
// first camera is included when the range starts at frame 0. (The online schedule is the fixed-lag
// smoother, backend/fixed_lag_smoother.h.)

#include "backend/backend_params.h"
#include "backend/factor_graph.h"

namespace dslam {

struct SolveOptions {
  int first_frame = 0;
  int last_frame = 0;
  int max_iterations = 50;
  int num_threads = 1;
  bool fix_cameras = false;  // SLAM+MOT's object stage: camera poses come from the static stage
  double function_tolerance = 1e-6;
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
