#pragma once
// The joint estimator: feeds frames into the factor graph and solves it on the configured schedule.
//  - batch: everything is kept and solved once at the end (Ceres, backend/graph_solver.h);
//  - window:W, the fixed-lag smoother: after every frame the last W frames are solved
//    (backend/window_solver.h) and what leaves the window is marginalised into priors
//    (backend/marginalisation.h) and handed to the result sink as final. Its per-frame cost and its
//    memory are bounded by the window, not by the sequence. With BackendParams::marginalisation exact,
//    what leaves is eliminated exactly into one dense prior (backend/exact_marginalisation.h) and the
//    window is solved by Ceres.

#include <chrono>
#include <functional>
#include <map>
#include <vector>

#include "backend/backend_params.h"
#include "backend/estimate.h"
#include "backend/factor_graph.h"
#include "backend/graph_builder.h"

namespace dslam {

struct EstimatorOptions {
  BuilderOptions builder;
  // When set, camera poses are held at the values it gives for each frame as the frame is added:
  // SLAM+MOT's object stage. It throws std::invalid_argument for a frame it has no pose for.
  std::function<SE3(int frame)> fixed_T_world_camera;
  // Where final estimates go as they become final; null: the estimator collects them and finish()
  // returns them all (runs that evaluate at the end). A streaming sink keeps memory bounded.
  EstimateSink* sink = nullptr;
  // Keep every solve's statistics (solveTimesMs() and the like, one entry per frame); false keeps only
  // the last solve's, for a service running for hours.
  bool keep_solve_history = true;
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
  // Solves (batch) or flushes the window, hands every estimate not yet final to the sink, and returns
  // the collected estimate (empty when an external sink was given). Call once, after the last frame.
  Estimate finish();
  // The newest frame's estimate (cost independent of the sequence length).
  FrameEstimate latest() const;

  // Wall time of the solve that followed each frame (sliding window only), milliseconds.
  const std::vector<double>& solveTimesMs() const { return solve_times_ms_; }
  // Size of each of those solves (residual blocks), the structural measure of its cost.
  const std::vector<int>& solveResidualBlocks() const { return solve_residual_blocks_; }
  const std::vector<int>& solveIterations() const { return solve_iterations_; }
  const FactorGraph& graph() const { return graph_; }
  const GraphBuilder& builder() const { return builder_; }

 private:
  struct SolveStats {
    int residual_blocks = 0;
    int iterations = 0;
  };
  // The sliding window after frame k was added: what leaves is marginalised, the window solved.
  SolveStats stepSparsified(int k);
  SolveStats stepExact(int k);
  void recordSolve(const SolveStats& stats, std::chrono::steady_clock::time_point start);
  void flush();  // hands everything still in the graph to the sink
  void batchCovariances();
  void handStepCovariance(int frame);  // to the sink, before the camera itself

  BackendParams params_;
  double frame_rate_hz_;
  EstimatorOptions options_;
  FactorGraph graph_;
  GraphBuilder builder_;
  CollectingSink collected_;
  EstimateSink* sink_;
  int cameras_final_ = 0;  // cameras [0, cameras_final_) were handed to the sink
  // Each camera's step covariance from the last solve that held both of its cameras, until it is final.
  std::map<int, Mat6> camera_step_covariance_;
  std::vector<double> solve_times_ms_;
  std::vector<int> solve_residual_blocks_;
  std::vector<int> solve_iterations_;
};

}  // namespace dslam
