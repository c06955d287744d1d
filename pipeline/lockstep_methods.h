#pragma once
// The three methods side by side on one stream of frames: the one driver of the estimators in every
// entry point (`run`, `sim`, `kitti-replay`, `serve`, through OnlineBackend and the streamed runs).
// Each frame is labelled once by the scene-flow classifier and added to every method, and each
// method's estimates go to its sink as they become final; nothing grows with the run's length. SLAM+MOT's object
// stage runs behind its static stage (static-only's estimator, shared): it takes frame k once camera k
// of the static stage is final, so it holds at most the static window's frames. Each method's estimates
// equal RunMethod's on the same labelled frames.

#include <chrono>
#include <deque>
#include <map>
#include <memory>
#include <optional>

#include "backend/estimator.h"
#include "backend/methods.h"
#include "frontend/dynamic_object_classifier.h"
#include "pipeline/run_config.h"

namespace dslam {

class LockstepMethods {
 public:
  // Runs the methods that have a sink (at least one); each sink must outlive this object. With `keep_solve_history`,
  // ours' estimator keeps its per-frame solve statistics (a run evaluated at its end; not a service).
  LockstepMethods(const RunConfig& config, double frame_rate_hz, const std::map<Method, EstimateSink*>& sinks,
                  bool keep_solve_history = false);
  ~LockstepMethods();
  LockstepMethods(const LockstepMethods&) = delete;
  LockstepMethods& operator=(const LockstepMethods&) = delete;

  // Labels the frame in place and adds it to every method; returns the newest frame's estimate (stamped):
  // ours' when ours runs, else the static stage's.
  std::optional<FrameEstimate> add(FrameMeasurement* frame);
  std::optional<FrameEstimate> add(FrameMeasurement frame) { return add(&frame); }
  // After the last frame: hands every remaining estimate to the sinks. Call once.
  void finish();
  // Seconds spent in the method's estimators (SLAM+MOT: its static stage too), labelling excluded.
  double wallTimeS(Method method) const;
  // Ours' estimator (nullptr when ours does not run): its window and statistics, for tests and reports.
  const Estimator* ours() const { return ours_.get(); }

 private:
  class StaticStageSink;
  class ObjectStageSink;
  void feedObjectStage();  // the waiting frames whose static camera is final

  using Clock = std::chrono::steady_clock;
  static double Seconds(Clock::time_point start);

  DynamicObjectClassifier classifier_;
  std::optional<FrameMeasurement> previous_;
  std::unique_ptr<Estimator> ours_, static_stage_, object_stage_;
  std::unique_ptr<StaticStageSink> static_sink_;
  std::unique_ptr<ObjectStageSink> object_sink_;
  std::deque<std::pair<int, SE3>> static_cameras_;  // final static-stage cameras the object stage needs
  std::deque<FrameMeasurement> object_stage_waiting_;
  double ours_s_ = 0.0, static_s_ = 0.0, object_s_ = 0.0;
};

}  // namespace dslam
