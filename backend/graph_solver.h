#pragma once
// Builds a Ceres problem from the factors of frames [first_frame, last_frame] and solves it in place.
// Variables only observed before first_frame are held constant (the sliding window's fixed past);
// the prior on the first camera is included when the range starts at frame 0.

#include "backend/backend_params.h"
#include "backend/factor_graph.h"

namespace dslam {

struct SolveOptions {
  int first_frame = 0;
  int last_frame = 0;
  int max_iterations = 50;
  int num_threads = 1;
  bool fix_cameras = false;
  int history_frames = 0;  // see BackendParams::window_history_frames
  double function_tolerance = 1e-6;  // SLAM+MOT's object stage: camera poses come from the static stage
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
