#pragma once
// One vehicle's online pipeline, middleware-free: assembled frames -> image front-end -> scene-flow
// classifier -> sliding-window estimator, one frame at a time, with the newest frame's estimate after
// each. It computes exactly what `dslam run` computes for ours (same code, same order), so that the
// estimates a DDS participant publishes equal those of a recorded run. Keeps the measurements so that
// the final results can be written when the service stops.

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "backend/estimator.h"
#include "data/sequence.h"
#include "frontend/dynamic_object_classifier.h"
#include "frontend/image_frontend.h"
#include "pipeline/run_config.h"

namespace dslam {

class VehiclePipeline {
 public:
  // The camera's intrinsics; its size is taken from the first frame when width/height are 0.
  VehiclePipeline(const RunConfig& config, const PinholeCamera& camera, double frame_rate_hz);

  // Throws std::invalid_argument for a frame the front-end rejects; the pipeline is then unchanged.
  FrameEstimate process(const ImageFrame& frame);

  int framesProcessed() const { return static_cast<int>(sequence_.frames.size()); }
  // The whole run so far, for the result files (ours only; no ground truth).
  const Sequence& sequence() const { return sequence_; }
  Estimate finish();

 private:
  RunConfig config_;
  PinholeCamera camera_;
  std::unique_ptr<ImageFrontend> frontend_;
  DynamicObjectClassifier classifier_;
  Estimator estimator_;
  Sequence sequence_;
};

}  // namespace dslam
