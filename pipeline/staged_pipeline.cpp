#include "pipeline/staged_pipeline.h"

#include <stdexcept>

#include "pipeline/thread_priority.h"

namespace dslam {

StagedPipeline::StagedPipeline(const RunConfig& config, const PinholeCamera& camera, double frame_rate_hz,
                               size_t queue_capacity, StagedPipelineCallbacks callbacks, StreamingFileSink* stream,
                               bool collect, const std::map<Method, EstimateSink*>& sinks)
    : config_(config),
      camera_(camera),
      frame_rate_hz_(frame_rate_hz),
      callbacks_(std::move(callbacks)),
      frames_(queue_capacity),
      measurements_(queue_capacity),
      backend_(config, frame_rate_hz, stream, collect, sinks) {
  config_.validate();
  if (!(frame_rate_hz > 0.0)) throw std::invalid_argument("the pipeline needs a positive frame rate");
  config_.frontend.frame_interval_s = 1.0 / frame_rate_hz;
  frontend_thread_ = std::thread([this] { runFrontend(); });
  backend_thread_ = std::thread([this] { runBackend(); });
}

StagedPipeline::~StagedPipeline() {
  abort_ = true;
  frames_.close();
  measurements_.close();
  if (frontend_thread_.joinable()) frontend_thread_.join();
  if (backend_thread_.joinable()) backend_thread_.join();
}

StagedPipeline::PreparedInput StagedPipeline::prepare(ImageFrame frame) const {
  PreparedInput input{std::move(frame), std::nullopt};
  try {
    input.prepared = ImageFrontend::Prepare(config_.frontend, input.frame);
  } catch (const std::exception&) {
    // The front-end meets the same fault when it processes the frame, and reports it as for any frame.
  }
  return input;
}

bool StagedPipeline::push(ImageFrame frame) { return frames_.push(PreparedInput{std::move(frame), std::nullopt}); }

bool StagedPipeline::pushPrepared(ImageFrame frame) { return frames_.push(prepare(std::move(frame))); }

bool StagedPipeline::pushNewest(ImageFrame frame) {
  PreparedInput input{std::move(frame), std::nullopt};
  return frames_.pushDropOldest(std::move(input), [](const PreparedInput& dropped_input, PreparedInput& next_input) {
    const ImageFrame& dropped = dropped_input.frame;
    ImageFrame& next = next_input.frame;
    // A dropped first frame (no increment into it) makes the next one the first.
    if (!dropped.odometry)
      next.odometry.reset();
    else if (next.odometry)
      next.odometry = Compose(*dropped.odometry, *next.odometry);
  });
}

void StagedPipeline::fail(std::exception_ptr error) {
  {
    std::lock_guard<std::mutex> lock(error_mutex_);
    if (!error_) error_ = error;
  }
  frames_.close();
  measurements_.close();
}

std::unique_ptr<ImageFrontend> MakeFrontend(const FrontendParams& params, PinholeCamera* camera, const ImageFrame& first) {
  if (camera->width == 0 || camera->height == 0) {
    if (const std::string bad = FindSizeMismatch(*camera, first.image.cols, first.image.rows); !bad.empty())
      throw std::invalid_argument("frame at " + std::to_string(first.t_ns) + " ns: " + bad);
    camera->width = first.image.cols, camera->height = first.image.rows;
  }
  return std::make_unique<ImageFrontend>(params, *camera);
}

void StagedPipeline::runFrontend() {
  int accepted = 0;
  // The odometry of frames the front-end rejected, carried into the next accepted frame's increment so
  // that the chain of poses stays whole.
  std::optional<OdometryMeasurement> carried;
  while (std::optional<PreparedInput> input = frames_.pop()) {
    if (abort_) return;
    if (skip_) continue;
    ImageFrame* frame = &input->frame;
    try {
      if (carried && frame->odometry) frame->odometry = Compose(*carried, *frame->odometry);
      frame->frame_index = accepted;  // the back-end numbers frames 0, 1, 2, ... as they reach it
      FrameTiming timing = frame->timing;
      timing.frontend_start_ns = SteadyClockNs();
      FrameMeasurement m;
      try {
        if (!frontend_) frontend_ = MakeFrontend(config_.frontend, &camera_, *frame);
        m = frontend_->process(*frame, input->prepared ? &*input->prepared : nullptr);
      } catch (const std::invalid_argument& e) {
        if (!callbacks_.on_rejected) throw;
        if (frame->odometry) carried = frame->odometry;  // already composed with what was carried before
        callbacks_.on_rejected(*frame, e.what());
        continue;
      }
      carried.reset();
      timing.frontend_end_ns = SteadyClockNs();
      ++accepted;
      if (callbacks_.on_measurement)
        callbacks_.on_measurement(m, frontend_->lastStats(), 1e-6 * static_cast<double>(timing.frontend_end_ns - timing.frontend_start_ns));
      if (!measurements_.push({std::move(m), timing})) return;
    } catch (...) {
      fail(std::current_exception());
      return;
    }
  }
  measurements_.close();  // every frame pushed went through: let the back-end drain and stop
}

void StagedPipeline::runBackend() {
  bool yielding = false;
  backend_nice_ = ThisThreadsNice();
  while (std::optional<TimedMeasurement> packet = measurements_.pop()) {
    if (abort_) return;
    if (skip_) continue;
    if (favour_frontend_ && !yielding) {
      // Measured on the demo run: the front-end's Lucas-Kanade splits each search with a worker thread,
      // and waits for it while the back-end holds the other core (2 % of the run's time on two cores).
      yielding = true;
      LowerThisThreadsPriority(kBackendYieldNiceSteps);
      backend_nice_ = ThisThreadsNice();
    }
    try {
      packet->timing.backend_start_ns = SteadyClockNs();
      const FrameEstimate estimate = backend_.add(&packet->measurement);
      packet->timing.backend_end_ns = SteadyClockNs();
      if (callbacks_.on_estimate) callbacks_.on_estimate(estimate, packet->measurement, packet->timing);
    } catch (...) {
      fail(std::current_exception());
      return;
    }
  }
}

MethodResult StagedPipeline::finish() {
  frames_.close();  // no more frames; the front-end drains its queue, then closes the back-end's
  if (frontend_thread_.joinable()) frontend_thread_.join();
  if (backend_thread_.joinable()) backend_thread_.join();
  {
    std::lock_guard<std::mutex> lock(error_mutex_);
    if (error_) std::rethrow_exception(error_);
  }
  return backend_.finish();
}

}  // namespace dslam
