#pragma once
// The three methods the evaluation runs side by side, all built from the same estimator:
//  - ours: cameras, static and dynamic structure and object motions in one factor graph;
//  - static-only: classical SLAM, object points discarded;
//  - SLAM+MOT: static-only cameras and map first, then each object's motion against those fixed cameras.

#include <functional>
#include <string>
#include <vector>

#include "backend/backend_params.h"
#include "backend/estimate.h"
#include "backend/estimator.h"
#include "data/measurements.h"

namespace dslam {

enum class Method { kOurs, kStaticOnly, kSlamMot };
std::string ToString(Method method);  // "ours", "static_only", "slam_mot"

struct MethodResult {
  Estimate estimate;
  double wall_time_s = 0.0;
  std::vector<double> solve_times_ms;  // sliding window: per frame
  // Ours: each frame's estimate as it stood right after that frame was added (what an online system
  // publishes); `estimate` is the final one.
  std::vector<FrameEstimate> online;
};

// Called after each frame added, with (frames done, total); may print progress.
using ProgressCallback = std::function<void(int, int)>;

MethodResult RunMethod(Method method, const BackendParams& params, double frame_rate_hz,
                       const std::vector<FrameMeasurement>& frames, const ProgressCallback& progress = {});

}  // namespace dslam
