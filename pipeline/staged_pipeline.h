#pragma once
// One camera's online pipeline with its stages in parallel (basalt's way): the image front-end and the
// back-end (OnlineBackend: classifier and ours) each run on their own thread, joined by bounded queues of
// value packets (ImageFrame in, FrameMeasurement between). A frame goes through the same code in the same
// order as in VehiclePipeline, so the estimates are the same; only the stages overlap in time.
//
// The measurements' queue applies back-pressure (the front-end waits) instead of dropping: a measurement
// refers to the previous frame's tracks, pose and per-frame object motion, so a dropped one would corrupt
// the next. Frames can be dropped before the front-end, where their odometry can still be composed:
// push() waits for room (every frame estimated, however late), pushNewest() drops the oldest waiting
// frame (the estimate never lags behind by more than the frames in the queues).

#include <atomic>
#include <exception>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "data/image_frame.h"
#include "frontend/image_frontend.h"
#include "pipeline/bounded_queue.h"
#include "pipeline/online_backend.h"
#include "pipeline/run_config.h"

namespace dslam {

struct StagedPipelineCallbacks {
  // Front-end thread, after each frame it accepted: the measurement (not yet classified), the
  // front-end's statistics of the frame and its front-end time in ms.
  std::function<void(const FrameMeasurement&, const FrontendFrameStats&, double)> on_measurement;
  // Back-end thread, after each frame: its estimate, its classified measurement and when it passed each
  // stage (the frame's timing with the front-end's and the back-end's times added).
  std::function<void(const FrameEstimate&, const FrameMeasurement&, const FrameTiming&)> on_estimate;
  // Front-end thread, for a frame the front-end rejected (the next good frame continues from the last
  // good one). When not set, a rejected frame stops the pipeline and finish() throws its error.
  std::function<void(const ImageFrame&, const std::string&)> on_rejected;
};

// The front-end for a stream whose first accepted frame is `first`. A camera without a size (a service
// given only intrinsics) takes the frame's, when the frame fits the intrinsics (FindSizeMismatch);
// otherwise std::invalid_argument, and the next frame is tried.
std::unique_ptr<ImageFrontend> MakeFrontend(const FrontendParams& params, PinholeCamera* camera, const ImageFrame& first);

class StagedPipeline {
 public:
  // `camera`: its size is taken from the first frame when width/height are 0. `queue_capacity`: frames
  // waiting before each stage.
  // `stream`, `collect` and `sinks` (the baselines beside ours, more sinks for ours): see OnlineBackend;
  // they are called from the back-end thread.
  StagedPipeline(const RunConfig& config, const PinholeCamera& camera, double frame_rate_hz, size_t queue_capacity,
                 StagedPipelineCallbacks callbacks, StreamingFileSink* stream = nullptr, bool collect = true,
                 const std::map<Method, EstimateSink*>& sinks = {});
  ~StagedPipeline();  // stops both stages (what is still queued is not processed)
  StagedPipeline(const StagedPipeline&) = delete;
  StagedPipeline& operator=(const StagedPipeline&) = delete;

  // Waits while the front-end's queue is full; false once the pipeline stopped (an error, or finish()).
  bool push(ImageFrame frame);
  // As push(), after preparing the frame on the caller's thread (ImageFrontend::Prepare: grey image, pyramid,
  // labels, mask edges), so that the front-end's thread only tracks: for a reader with time to spare
  // (`dslam run`'s). A service's receiving thread must hand its frames over at once: preparing there made
  // `serve` drop 6 to 8 of 60 frames at 20 Hz (bench_dds_latency) instead of none.
  bool pushPrepared(ImageFrame frame);
  // Never waits: when the front-end's queue is full, its oldest frame is dropped (counted in
  // framesDropped()) and its odometry composed into the frame after it, so that a pipeline that falls
  // behind estimates the newest frames instead of an ever older backlog. With a queue capacity of 1 a
  // frame waits at most for the frame before it. False once the pipeline stopped.
  bool pushNewest(ImageFrame frame);
  uint64_t framesDropped() const { return frames_.dropped(); }
  // For a run whose rate is what counts (`dslam run` reading a dataset): from its next frame on, the
  // back-end's thread yields the CPU to the front-end's (kBackendYieldNiceSteps nice levels lower), the stage
  // that sets the rate while the back-end has slack. A service keeps both equal, as is the default: there
  // each frame's estimate is wanted as soon as it can be made. The estimates are the same either way.
  void favourFrontend() { favour_frontend_ = true; }
  static constexpr int kBackendYieldNiceSteps = 5;
  // The back-end thread's nice value: its start's, then the one favourFrontend() set (for tests).
  int backendNice() const { return backend_nice_; }
  // Processes everything pushed, joins the stages and returns ours' result; throws a stage's error.
  MethodResult finish();
  // After finish(): the seconds a method spent in its estimators.
  double wallTimeS(Method method) const { return backend_.wallTimeS(method); }
  // From any thread, also while finish() waits: the frames and measurements still queued are dropped
  // instead of processed (what is in progress completes), so that finish() returns at once and flushes
  // what was estimated. For a service asked twice to stop.
  void skipQueued() { skip_ = true; }

 private:
  void runFrontend();
  void runBackend();
  void fail(std::exception_ptr error);

  struct PreparedInput {  // a packet into the front-end: the frame, and what the pushing thread took from it
    ImageFrame frame;
    std::optional<PreparedFrame> prepared;  // none: the frame could not be prepared (the front-end says why)
  };
  struct TimedMeasurement {  // a packet between the stages
    FrameMeasurement measurement;
    FrameTiming timing;
  };
  PreparedInput prepare(ImageFrame frame) const;

  RunConfig config_;
  PinholeCamera camera_;
  double frame_rate_hz_;
  StagedPipelineCallbacks callbacks_;
  BoundedQueue<PreparedInput> frames_;
  BoundedQueue<TimedMeasurement> measurements_;
  std::unique_ptr<ImageFrontend> frontend_;
  OnlineBackend backend_;
  std::mutex error_mutex_;
  std::exception_ptr error_;
  std::atomic<bool> abort_{false};  // the destructor: stop without draining
  std::atomic<bool> skip_{false};   // skipQueued(): drop what is queued, still finish
  std::atomic<bool> favour_frontend_{false};
  std::atomic<int> backend_nice_{0};
  std::thread frontend_thread_, backend_thread_;
};

}  // namespace dslam
