#include "pipeline/lockstep_methods.h"

#include <stdexcept>
#include <utility>

namespace dslam {

// Static-only's estimates, and SLAM+MOT's cameras and static points, which are the same ones; the
// final cameras are also kept for the object stage.
class LockstepMethods::StaticStageSink : public EstimateSink {
 public:
  StaticStageSink(EstimateSink* static_only, EstimateSink* slam_mot, std::deque<std::pair<int, SE3>>* cameras)
      : static_only_(static_only), slam_mot_(slam_mot), cameras_(cameras) {}
  void cameraFinal(int frame, const SE3& T_world_camera) override {
    for (EstimateSink* s : {static_only_, slam_mot_})
      if (s) s->cameraFinal(frame, T_world_camera);
    if (slam_mot_) cameras_->emplace_back(frame, T_world_camera);
  }
  void motionFinal(const ObjectMotionEstimate&) override {}  // the static stage estimates no object
  void pointFinal(const PointEstimate& point) override {
    for (EstimateSink* s : {static_only_, slam_mot_})
      if (s) s->pointFinal(point);
  }
  void cameraStepCovariance(int frame, const Mat6& covariance) override {
    for (EstimateSink* s : {static_only_, slam_mot_})
      if (s) s->cameraStepCovariance(frame, covariance);
  }

 private:
  EstimateSink* static_only_;
  EstimateSink* slam_mot_;
  std::deque<std::pair<int, SE3>>* cameras_;
};

// SLAM+MOT's object motions and object points (its cameras are the static stage's).
class LockstepMethods::ObjectStageSink : public EstimateSink {
 public:
  explicit ObjectStageSink(EstimateSink* slam_mot) : slam_mot_(slam_mot) {}
  void cameraFinal(int, const SE3&) override {}
  void motionFinal(const ObjectMotionEstimate& motion) override { slam_mot_->motionFinal(motion); }
  void pointFinal(const PointEstimate& point) override { slam_mot_->pointFinal(point); }

 private:
  EstimateSink* slam_mot_;
};

namespace {
EstimateSink* SinkOf(const std::map<Method, EstimateSink*>& sinks, Method method) {
  const auto it = sinks.find(method);
  return it == sinks.end() ? nullptr : it->second;
}
}  // namespace

LockstepMethods::LockstepMethods(const RunConfig& config, double frame_rate_hz,
                                 const std::map<Method, EstimateSink*>& sinks, bool keep_solve_history)
    : classifier_(config.classifier, frame_rate_hz) {
  config.validate();
  EstimateSink* ours = SinkOf(sinks, Method::kOurs);
  EstimateSink* static_only = SinkOf(sinks, Method::kStaticOnly);
  EstimateSink* slam_mot = SinkOf(sinks, Method::kSlamMot);
  if (!ours && !static_only && !slam_mot) throw std::invalid_argument("no method to run: every sink is null");
  EstimatorOptions options;
  options.keep_solve_history = false;  // a long run keeps no per-frame statistics
  if (ours) {
    EstimatorOptions ours_options = options;
    ours_options.keep_solve_history = keep_solve_history;
    ours_options.sink = ours;
    ours_ = std::make_unique<Estimator>(config.backend, frame_rate_hz, ours_options);
  }
  if (static_only || slam_mot) {
    static_sink_ = std::make_unique<StaticStageSink>(static_only, slam_mot, &static_cameras_);
    EstimatorOptions static_options = options;
    static_options.builder.use_objects = false;
    static_options.sink = static_sink_.get();
    static_stage_ = std::make_unique<Estimator>(config.backend, frame_rate_hz, static_options);
  }
  if (slam_mot) {
    // As RunMethod's object stage: the object factors alone, cameras held at the static stage's.
    object_sink_ = std::make_unique<ObjectStageSink>(slam_mot);
    EstimatorOptions object_options = options;
    object_options.builder.use_static_points = false;
    object_options.builder.use_odometry = false;
    object_options.sink = object_sink_.get();
    object_options.fixed_T_world_camera = [this](int k) {
      while (!static_cameras_.empty() && static_cameras_.front().first < k) static_cameras_.pop_front();
      if (static_cameras_.empty() || static_cameras_.front().first != k)
        throw std::logic_error("SLAM+MOT: static camera " + std::to_string(k) + " is not final");
      return static_cameras_.front().second;
    };
    BackendParams tracker = config.backend;
    tracker.default_mode = config.backend.slam_mot_mode;
    tracker.mode_per_object.clear();
    object_stage_ = std::make_unique<Estimator>(tracker, frame_rate_hz, object_options);
  }
}

LockstepMethods::~LockstepMethods() = default;

double LockstepMethods::Seconds(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

std::optional<FrameEstimate> LockstepMethods::add(FrameMeasurement* frame) {
  if (previous_) classifier_.label(*previous_, frame);
  std::optional<FrameEstimate> latest;
  if (ours_) {
    const auto start = Clock::now();
    ours_->addFrame(*frame);
    latest = ours_->latest();
    latest->t_ns = frame->t_ns;
    ours_s_ += Seconds(start);
  }
  if (static_stage_) {
    const auto start = Clock::now();
    static_stage_->addFrame(*frame);
    if (!latest) {
      latest = static_stage_->latest();
      latest->t_ns = frame->t_ns;
    }
    static_s_ += Seconds(start);
  }
  if (object_stage_) {
    object_stage_waiting_.push_back(*frame);
    feedObjectStage();
  }
  previous_ = *frame;
  return latest;
}

void LockstepMethods::feedObjectStage() {
  const auto start = Clock::now();
  while (!object_stage_waiting_.empty() && !static_cameras_.empty() &&
         static_cameras_.back().first >= object_stage_waiting_.front().frame_index) {
    object_stage_->addFrame(object_stage_waiting_.front());
    object_stage_waiting_.pop_front();
  }
  object_s_ += Seconds(start);
}

void LockstepMethods::finish() {
  if (ours_) {
    const auto start = Clock::now();
    ours_->finish();
    ours_s_ += Seconds(start);
  }
  if (static_stage_) {
    const auto start = Clock::now();
    static_stage_->finish();
    static_s_ += Seconds(start);
  }
  if (object_stage_) {
    feedObjectStage();
    if (!object_stage_waiting_.empty())
      throw std::logic_error("SLAM+MOT: frame " + std::to_string(object_stage_waiting_.front().frame_index) +
                             " never got its static camera");
    const auto start = Clock::now();
    object_stage_->finish();
    object_s_ += Seconds(start);
  }
}

double LockstepMethods::wallTimeS(Method method) const {
  switch (method) {
    case Method::kOurs: return ours_s_;
    case Method::kStaticOnly: return static_s_;
    case Method::kSlamMot: return static_s_ + object_s_;
  }
  return 0.0;
}

}  // namespace dslam
