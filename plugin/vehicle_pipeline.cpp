#include "plugin/vehicle_pipeline.h"

namespace dslam {

VehiclePipeline::VehiclePipeline(const RunConfig& config, const PinholeCamera& camera, double frame_rate_hz)
    : config_(config), camera_(camera), backend_(config, frame_rate_hz) {
  config_.validate();
  config_.frontend.frame_interval_s = 1.0 / frame_rate_hz;
}

FrameEstimate VehiclePipeline::process(const ImageFrame& frame_in) {
  if (!frontend_) {
    if (camera_.width == 0 || camera_.height == 0) camera_.width = frame_in.image.cols, camera_.height = frame_in.image.rows;
    frontend_ = std::make_unique<ImageFrontend>(config_.frontend, camera_);
  }
  // The back-end numbers frames 0, 1, 2, ... as they reach it.
  ImageFrame frame = frame_in;
  frame.frame_index = framesProcessed();
  FrameMeasurement m = frontend_->process(frame);
  return backend_.add(&m);
}

}  // namespace dslam
