#include "pipeline/image_run.h"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>

#include "data/frame_timing.h"
#include "data/kitti_dataset.h"
#include "data/ping_pong_replay.h"
#include "output/object_summary.h"
#include "pipeline/method_output.h"
#include "pipeline/reference_objects.h"
#include "pipeline/staged_pipeline.h"

namespace dslam {
namespace {
using Clock = std::chrono::steady_clock;

// What the run records of each frame the front-end produced: the measurement, the front-end log and the
// summary's sums. Called in frame order, from one thread at a time.
class FrontendRecorder {
 public:
  FrontendRecorder(int frames, std::ostream* progress, std::mutex* progress_mutex, std::ostream* frame_log,
                   Sequence* seq)
      : frames_(frames), progress_(progress), progress_mutex_(progress_mutex), frame_log_(frame_log), seq_(seq) {}

  // With masks made by the run on a dataset that has its own: the objects are matched to the dataset's
  // (pipeline/reference_objects.h), which also say which objects are large enough to count.
  void useReferenceMasks(ReferenceObjectMatcher* matcher) { reference_ = matcher; }

  void record(const FrameMeasurement& m, const FrontendFrameStats& st, double frontend_ms) {
    const int k = frames_recorded_++;
    if (seq_) seq_->frames.push_back(m);
    frontend_ms_ += frontend_ms;
    if (reference_)
      reference_->match(k, m);
    else
      for (int label : st.mask_labels) visible_.insert({k, label});
    if (frame_log_) {
      if (k == 0)
        *frame_log_ << "frame,object_id,flowed,tracked,added,measured,motion_rejected,pnp_inliers,median_fb_px,"
                       "odometry_rejected,previous,survival,reacquired\n";
      *frame_log_ << k << ",0,-1," << st.static_tracked << ',' << st.static_new << ",1,0," << st.pnp_inliers << ','
                  << st.median_fb_error_px << ',' << (st.odometry_rejected ? 1 : 0) << ",,,\n";
      for (const auto& [id, c] : st.object_counts) {
        *frame_log_ << k << ',' << id << ',' << c.flowed << ',' << c.tracked << ',' << c.added << ','
                    << (c.measured ? 1 : 0) << ',' << (c.motion_rejected ? 1 : 0) << ',' << st.pnp_inliers << ','
                    << st.median_fb_error_px << ',' << (st.odometry_rejected ? 1 : 0) << ',' << c.previous << ',';
        // The share of its tracks that lived on into this frame (blank for an object new in it).
        if (c.previous > 0) *frame_log_ << static_cast<double>(c.tracked) / c.previous;
        *frame_log_ << ',' << c.reacquired << '\n';
      }
      frame_log_->flush();  // whole rows only, should the run be stopped
    }
    s_.mean_static_tracks += st.static_tracked + st.static_new;
    s_.mean_object_points += st.object_points_tracked + st.object_points_new;
    s_.mean_pnp_inliers += st.pnp_inliers;
    s_.odometry_rejected += st.odometry_rejected ? 1 : 0;
    if (k > 0) fb_medians_.push_back(st.median_fb_error_px);
    if (progress_ && ((k + 1) % std::max(1, frames_ / 10) == 0 || k + 1 == frames_)) {
      const double elapsed = std::chrono::duration<double>(Clock::now() - start_).count();
      std::lock_guard<std::mutex> lock(*progress_mutex_);
      *progress_ << "  front-end: frame " << k + 1 << "/" << frames_ << ", " << (k + 1) / elapsed << " frames/s, "
                 << st.static_tracked << " static tracks kept + " << st.static_new << " new, " << st.objects
                 << " objects" << std::endl;
    }
  }

  bool visible(int k, int label) const {
    return reference_ ? reference_->visible(k, label) : visible_.count({k, label}) > 0;
  }

  // A streamed run has marked frame k in its ground truth (or has none): its masks need not be kept.
  void forget(int k) {
    visible_.erase(visible_.lower_bound({k, std::numeric_limits<int>::min()}),
                   visible_.lower_bound({k + 1, std::numeric_limits<int>::min()}));
  }

  // Marks in `gt` what frame k (recorded) saw, and with reference masks which run object each is.
  void observe(int k, double object_max_range_m, GroundTruth* gt) const {
    ObserveFrame(k, object_max_range_m, [&](int frame, int id) { return visible(frame, id); }, gt);
    if (!reference_) return;
    if (!gt->run_object_ids) gt->run_object_ids.emplace();
    const auto& ids = reference_->runObjectIds();
    for (auto it = ids.lower_bound({k, std::numeric_limits<int>::min()}); it != ids.end() && it->first.first == k; ++it)
      gt->run_object_ids->insert(*it);
  }

  ImageRunSummary summary(double read_s) {
    ImageRunSummary s = s_;
    const int frames = frames_recorded_;
    s.frames = frames;
    if (frames > 0) {
      s.frontend_ms_per_frame = frontend_ms_ / frames;
      s.read_ms_per_frame = 1000.0 * read_s / frames;
      s.mean_static_tracks /= frames;
      s.mean_object_points /= frames;
      s.mean_pnp_inliers /= std::max(1, frames - 1);
    }
    if (!fb_medians_.empty()) {
      std::nth_element(fb_medians_.begin(), fb_medians_.begin() + fb_medians_.size() / 2, fb_medians_.end());
      s.median_fb_error_px = fb_medians_[fb_medians_.size() / 2];
    }
    return s;
  }

 private:
  int frames_;
  std::ostream* progress_;
  std::mutex* progress_mutex_;
  std::ostream* frame_log_;
  Sequence* seq_;  // null: the measurements are not kept
  int frames_recorded_ = 0;
  const Clock::time_point start_ = Clock::now();
  std::set<std::pair<int, int>> visible_;  // (frame, mask label) large enough to be an object
  ReferenceObjectMatcher* reference_ = nullptr;
  ImageRunSummary s_;
  std::vector<double> fb_medians_;
  double frontend_ms_ = 0.0;
};

// Reads frame k of the dataset and puts the configured masks on it; with reference masks (the dataset's
// own, when the run makes its own), keeps the dataset's for the matcher.
class FrameReader {
 public:
  FrameReader(const ImageDataset& dataset, const RunConfig& config, FrontendRecorder* recorder, bool ping_pong = false)
      : dataset_(dataset), masks_(MaskSourceOf(config)), ping_pong_(ping_pong) {
    if (ping_pong_ && dataset.size() < 2)
      throw std::invalid_argument("replaying " + dataset.name() + " forwards and backwards needs 2 frames or more");
    if (!ping_pong_ && config.masks.source != MaskSourceKind::kDataset && dataset.groundTruth() && dataset.hasMasks()) {
      reference_.emplace(dataset.camera(), config.frontend.min_mask_area_pct);
      recorder->useReferenceMasks(&*reference_);
    }
  }
  ImageFrame read(int k) {
    ImageFrame frame = ping_pong_ ? readPingPong(k) : dataset_.read(k);
    if (reference_ && !frame.instance_ids.empty()) reference_->keep(k, frame.instance_ids);
    ApplyMaskSource(masks_, dataset_.camera(), frame);
    return frame;
  }
  const ReferenceObjectMatcher* reference() const { return reference_ ? &*reference_ : nullptr; }

 private:
  // Step i of the forwards-and-backwards drive, as recorded (no reference masks: nothing is evaluated).
  ImageFrame readPingPong(int i) const {
    const int n = dataset_.size();
    ImageFrame frame = dataset_.read(PingPongFrame(i, n));
    const int64_t period_ns = static_cast<int64_t>(1e9 / dataset_.frameRateHz());
    ToPingPongStep(i, n, period_ns, [&](int k) { return dataset_.odometryAt(k); }, &frame);
    return frame;
  }

  const ImageDataset& dataset_;
  MaskSourceParams masks_;
  bool ping_pong_;
  std::optional<ReferenceObjectMatcher> reference_;
};

// Hands every call to `sink` with `mutex` held: the methods' outputs are fed from the back-end thread
// while the front-end thread adds what each frame saw to the ground truth they read.
class LockedSink : public EstimateSink {
 public:
  LockedSink(EstimateSink* sink, std::mutex* mutex) : sink_(sink), mutex_(mutex) {}
  void cameraFinal(int frame, const SE3& T_world_camera) override {
    std::lock_guard<std::mutex> lock(*mutex_);
    sink_->cameraFinal(frame, T_world_camera);
  }
  void motionFinal(const ObjectMotionEstimate& motion) override {
    std::lock_guard<std::mutex> lock(*mutex_);
    sink_->motionFinal(motion);
  }
  void pointFinal(const PointEstimate& point) override {
    std::lock_guard<std::mutex> lock(*mutex_);
    sink_->pointFinal(point);
  }
  void cameraStepCovariance(int frame, const Mat6& covariance) override {
    std::lock_guard<std::mutex> lock(*mutex_);
    sink_->cameraStepCovariance(frame, covariance);
  }

 private:
  EstimateSink* sink_;
  std::mutex* mutex_;
};

// Ours' final motions of the frames the caller asked for (the report's overlays).
class KeptMotions : public EstimateSink {
 public:
  explicit KeptMotions(const std::set<int>& frames) : frames_(frames) {}
  void cameraFinal(int, const SE3&) override {}
  void motionFinal(const ObjectMotionEstimate& motion) override {
    if (frames_.count(motion.frame)) kept.push_back(motion);
  }
  void pointFinal(const PointEstimate&) override {}
  std::vector<ObjectMotionEstimate> kept;

 private:
  const std::set<int>& frames_;
};

}  // namespace

int FramesToRun(const ImageDataset& dataset, int max_frames) {
  return max_frames > 0 ? std::min(max_frames, dataset.size()) : dataset.size();
}

Sequence RunImageFrontend(const ImageDataset& dataset, const RunConfig& config, int max_frames, std::ostream* progress,
                          ImageRunSummary* summary, std::ostream* frame_log) {
  config.validate();
  const int frames = FramesToRun(dataset, max_frames);
  Sequence seq;
  seq.name = dataset.name();
  seq.frame_rate_hz = dataset.frameRateHz();
  std::mutex progress_mutex;
  FrontendRecorder recorder(frames, progress, &progress_mutex, frame_log, &seq);
  FrameReader reader(dataset, config, &recorder);
  FrontendParams frontend_params = config.frontend;
  frontend_params.frame_interval_s = 1.0 / dataset.frameRateHz();
  ImageFrontend frontend(frontend_params, dataset.camera());
  double read_s = 0.0;
  for (int k = 0; k < frames; ++k) {
    const auto t0 = Clock::now();
    ImageFrame frame = reader.read(k);
    const auto t1 = Clock::now();
    const FrameMeasurement m = frontend.process(frame);
    read_s += std::chrono::duration<double>(t1 - t0).count();
    recorder.record(m, frontend.lastStats(), 1000.0 * SecondsSince(t1));
  }

  ImageRunSummary s = recorder.summary(read_s);
  if (dataset.groundTruth()) {
    s.has_ground_truth = true;
    seq.gt = ToGroundTruth(*dataset.groundTruth(), frames, config.frontend.object_max_distance_m,
                           [&](int k, int id) { return recorder.visible(k, id); });
    if (const ReferenceObjectMatcher* reference = reader.reference()) seq.gt.run_object_ids = reference->runObjectIds();
  }
  if (summary) *summary = s;
  return seq;
}

ImageRunResult RunImageStreamed(const ImageDataset& dataset, const RunConfig& config, const ImageRunOptions& options) {
  config.validate();
  if (options.methods.empty()) throw std::invalid_argument("the run names no method");
  if (options.ping_pong && options.max_frames <= 0)
    throw std::invalid_argument("a forwards-and-backwards replay needs a number of frames");
  const int frames = options.ping_pong ? options.max_frames : FramesToRun(dataset, options.max_frames);
  const double rate = dataset.frameRateHz();
  if (!options.out_dir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(options.out_dir, ec);
    if (ec) throw std::runtime_error("cannot create output directory " + options.out_dir + ": " + ec.message());
  }
  std::mutex progress_mutex;
  FrontendRecorder recorder(frames, options.progress, &progress_mutex, options.frame_log, nullptr);
  FrameReader reader(dataset, config, &recorder, options.ping_pong);

  // The ground truth learns frame by frame what the front-end saw; it and the outputs that read it are
  // guarded by one mutex (the front-end thread writes, the back-end thread's sinks read).
  std::mutex outputs_mutex;
  std::optional<GroundTruth> gt;
  if (dataset.groundTruth() && !options.ping_pong) gt = ToUnobservedGroundTruth(*dataset.groundTruth(), frames);
  MethodOutputs outputs =
      MakeMethodOutputs(options.methods, options.out_dir, gt ? &*gt : nullptr, rate, options.object_category);
  std::vector<std::unique_ptr<EstimateSink>> wrappers;
  std::map<Method, EstimateSink*> sinks;
  KeptMotions kept(options.keep_frames);
  for (auto& [method, output] : outputs) {
    EstimateSink* sink = output.get();
    if (method == Method::kOurs && !options.keep_frames.empty())
      sink = wrappers.emplace_back(std::make_unique<TeeSink>(sink, &kept)).get();
    sinks[method] = wrappers.emplace_back(std::make_unique<LockedSink>(sink, &outputs_mutex)).get();
  }
  std::vector<int64_t> t_ns;  // a stamp a frame, for the ground truth's trajectory file
  t_ns.reserve(frames);

  // Frames wait at most this many deep before each stage: enough to ride out a slow frame.
  constexpr size_t kQueueCapacity = 4;
  StagedPipelineCallbacks callbacks;
  callbacks.on_measurement = [&](const FrameMeasurement& m, const FrontendFrameStats& st, double ms) {
    recorder.record(m, st, ms);
    std::lock_guard<std::mutex> lock(outputs_mutex);
    if (gt) recorder.observe(m.frame_index, config.frontend.object_max_distance_m, &*gt);
    recorder.forget(m.frame_index);
    t_ns.push_back(m.t_ns);
    for (auto& [method, output] : outputs) output->frameMade(m.frame_index, m.t_ns);
  };
  const int step = std::max(1, frames / 10);
  StageLatency latency;
  const bool with_ours = outputs.count(Method::kOurs) > 0;
  callbacks.on_estimate = [&](const FrameEstimate& e, const FrameMeasurement&, const FrameTiming& timing) {
    if (with_ours) {
      std::lock_guard<std::mutex> lock(outputs_mutex);
      outputs.at(Method::kOurs)->onlinePose(e.t_ns, e.T_world_camera);
    }
    FrameTiming t = timing;
    t.published_ns = SteadyClockNs();
    latency.add(t);
    if (options.progress && ((e.frame + 1) % step == 0 || e.frame + 1 == frames)) {
      std::lock_guard<std::mutex> lock(progress_mutex);
      *options.progress << "  methods: frame " << e.frame + 1 << "/" << frames << std::endl;
    }
  };
  // Ours runs when asked for; without it, each frame's estimate (on_estimate) is static-only's.
  StagedPipeline pipeline(config, dataset.camera(), rate, kQueueCapacity, callbacks, nullptr, /*collect=*/false, sinks);
  pipeline.favourFrontend();  // a dataset is read as fast as it can be estimated: the rate counts, not each frame's latency
  double read_s = 0.0;
  std::string stopped_by;
  std::map<int, KeptFrame> kept_frames;
  for (int k = 0; k < frames; ++k) {
    const int64_t received_ns = SteadyClockNs();
    ImageFrame frame;
    try {
      frame = reader.read(k);
    } catch (const std::exception& e) {
      // A frame that cannot be read ends the run there: the frames before it are estimated to the end and
      // written whole, and the caller reports the error (nothing to keep when it is the first).
      if (k == 0) throw;
      stopped_by = e.what();
      break;
    }
    frame.timing.received_ns = received_ns;
    frame.timing.assembled_ns = SteadyClockNs();
    read_s += 1e-9 * static_cast<double>(frame.timing.assembled_ns - received_ns);
    std::optional<KeptFrame> keep;
    if (options.keep_frames.count(k)) keep = KeptFrame{frame.image.clone(), frame.instance_ids.clone()};
    if (!pipeline.pushPrepared(std::move(frame))) break;  // a stage failed: finish() throws its error
    if (keep) kept_frames[k] = std::move(*keep);
    if (options.after_frame) options.after_frame(k + 1);
  }
  pipeline.finish();

  ImageRunResult result;
  result.stopped_by = stopped_by;
  result.summary = recorder.summary(read_s);
  result.summary.latency = latency.summary();
  result.summary.has_ground_truth = gt.has_value();
  result.outcomes =
      FinishMethodOutputs(outputs, [&](Method m) { return pipeline.wallTimeS(m); }, &result.ours_objects);
  result.kept_motions = std::move(kept.kept);
  result.kept_frames = std::move(kept_frames);
  if (!options.out_dir.empty()) {
    if (gt && !stopped_by.empty()) TruncateGroundTruth(static_cast<int>(t_ns.size()), &*gt);  // the frames run
    WriteGroundTruthFiles(options.out_dir, gt ? *gt : GroundTruth{}, t_ns);
    if (with_ours) WriteObjectsCsv(options.out_dir + "/objects.csv", result.ours_objects);
  }
  return result;
}

}  // namespace dslam
