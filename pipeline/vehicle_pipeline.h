#pragma once
// One vehicle's online pipeline, middleware-free and on the caller's thread: assembled frames -> image
// front-end -> OnlineBackend (scene-flow classifier, ours in the sliding window), one frame at a time,
// with the newest frame's estimate after each. It computes exactly what `dslam run` computes for ours
// (same code, same order), so it is the reference the DDS participant's staged pipeline
// (pipeline/staged_pipeline.h) is tested against.

#include <memory>

#include "frontend/image_frontend.h"
#include "pipeline/online_backend.h"
#include "pipeline/run_config.h"

namespace dslam {

class VehiclePipeline {
 public:
  // The camera's intrinsics; its size is taken from the first frame when width/height are 0.
  VehiclePipeline(const RunConfig& config, const PinholeCamera& camera, double frame_rate_hz);

  // Throws std::invalid_argument for a frame the front-end or the back-end refuses; the pipeline is then
  // unchanged (the front-end takes its step back when the back-end refuses).
  FrameEstimate process(const ImageFrame& frame);

  int framesProcessed() const { return backend_.framesAdded(); }
  MethodResult finish() { return backend_.finish(); }

 private:
  RunConfig config_;
  PinholeCamera camera_;
  std::unique_ptr<ImageFrontend> frontend_;
  OnlineBackend backend_;
};

}  // namespace dslam
