#pragma once
// The joint estimator: feeds frames into the factor graph and solves it on the configured schedule
// (batch: once at the end; sliding window: the last W frames after every frame).

#include <vector>

#include "backend/backend_params.h"
#include "backend/estimate.h"
#include "backend/factor_graph.h"
#include "backend/graph_builder.h"
#include "backend/graph_solver.h"

namespace dslam {

struct EstimatorOptions {
  BuilderOptions builder;
  // When set (one pose per frame), camera poses are held at these values: SLAM+MOT's object stage.
  const std::vector<SE3>* fixed_T_world_camera = nullptr;
};

// The current estimate of the newest frame: its camera pose and the object motions into it. This is
// what a vehicle can act on at once; later sliding-window solves may still refine both.
struct FrameEstimate {
  int frame = 0;
  int64_t t_ns = 0;
  SE3 T_world_camera;
  std::vector<ObjectMotionEstimate> object_motions;
};

class Estimator {
 public:
  Estimator(const BackendParams& params, double frame_rate_hz, const EstimatorOptions& options = {});

  void addFrame(const FrameMeasurement& frame);
  // Runs the final batch solve (batch schedule) and extracts the estimate.
  Estimate finish();
  // The newest frame's estimate (cost independent of the sequence length).
  FrameEstimate latest() const;

  // Wall time of the solve that followed each frame (sliding window only), milliseconds.
  const std::vector<double>& solveTimesMs() const { return solve_times_ms_; }
  // Size of each of those solves (residual blocks), the structural measure of its cost.
  const std::vector<int>& solveResidualBlocks() const { return solve_residual_blocks_; }
  const std::vector<int>& solveIterations() const { return solve_iterations_; }
  const FactorGraph& graph() const { return graph_; }

 private:
  Estimate extract() const;
  ObjectMotionEstimate motionEstimate(const ObjectTransition& transition) const;
  SolveOptions solveOptions(int first_frame, int last_frame, int max_iterations) const;

  BackendParams params_;
  double frame_rate_hz_;
  EstimatorOptions options_;
  FactorGraph graph_;
  GraphBuilder builder_;
  std::vector<double> solve_times_ms_;
  std::vector<int> solve_residual_blocks_;
  std::vector<int> solve_iterations_;
};

}  // namespace dslam
