#pragma once
// The three methods side by side on one stream of frames, for runs whose memory must not grow with
// their length (`dslam sim`): each frame is labelled once by the scene-flow classifier and added to
// every method, and each method's estimates go to its sink as they become final. SLAM+MOT's object
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
  // Runs the methods that have a sink; each sink must outlive this object.
  LockstepMethods(const RunConfig& config, double frame_rate_hz, const std::map<Method, EstimateSink*>& sinks);
  ~LockstepMethods();
  LockstepMethods(const LockstepMethods&) = delete;
  LockstepMethods& operator=(const LockstepMethods&) = delete;

  // Labels the frame and adds it to every method; returns ours' newest estimate (stamped) when ours runs.
  std::optional<FrameEstimate> add(FrameMeasurement frame);
  // After the last frame: hands every remaining estimate to the sinks. Call once.
  void finish();
  // Seconds spent in the method's estimators (SLAM+MOT: its static stage too), labelling excluded.
  double wallTimeS(Method method) const;

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
