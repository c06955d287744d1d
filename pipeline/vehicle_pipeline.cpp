#include "pipeline/vehicle_pipeline.h"

#include "pipeline/staged_pipeline.h"

namespace dslam {

VehiclePipeline::VehiclePipeline(const RunConfig& config, const PinholeCamera& camera, double frame_rate_hz)
    : config_(config), camera_(camera), backend_(config, frame_rate_hz) {
  config_.validate();
  config_.frontend.frame_interval_s = 1.0 / frame_rate_hz;
}

FrameEstimate VehiclePipeline::process(const ImageFrame& frame_in) {
  if (!frontend_) frontend_ = MakeFrontend(config_.frontend, &camera_, frame_in);
  // The back-end numbers frames 0, 1, 2, ... as they reach it.
  ImageFrame frame = frame_in;
  frame.frame_index = framesProcessed();
  FrameMeasurement m = frontend_->process(frame);
  try {
    return backend_.add(&m);
  } catch (...) {
    frontend_->undoLast();  // both stages take the frame, or neither
    throw;
  }
}

}  // namespace dslam
