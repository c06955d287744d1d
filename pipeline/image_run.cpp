#include "pipeline/image_run.h"

#include <algorithm>
#include <chrono>
#include <mutex>
#include <optional>
#include <set>

#include "data/frame_timing.h"
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
    const int k = static_cast<int>(seq_->frames.size());
    seq_->frames.push_back(m);
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

  void setLatency(std::vector<StageLatencySummary> latency) { s_.latency = std::move(latency); }

  ImageRunSummary summary(double read_s) {
    ImageRunSummary s = s_;
    const int frames = static_cast<int>(seq_->frames.size());
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
  Sequence* seq_;
  const Clock::time_point start_ = Clock::now();
  std::set<std::pair<int, int>> visible_;  // (frame, mask label) large enough to be an object
  ReferenceObjectMatcher* reference_ = nullptr;
  ImageRunSummary s_;
  std::vector<double> fb_medians_;
  double frontend_ms_ = 0.0;
};

}  // namespace

Sequence RunImageFrontend(const ImageDataset& dataset, const RunConfig& config, int max_frames, std::ostream* progress,
                          ImageRunSummary* summary, std::ostream* frame_log, MethodResult* ours,
                          StreamingFileSink* stream) {
  config.validate();
  const int frames = max_frames > 0 ? std::min(max_frames, dataset.size()) : dataset.size();
  Sequence seq;
  seq.name = dataset.name();
  seq.frame_rate_hz = dataset.frameRateHz();
  std::mutex progress_mutex;
  FrontendRecorder recorder(frames, progress, &progress_mutex, frame_log, &seq);
  std::optional<ReferenceObjectMatcher> reference;
  if (config.masks.source != MaskSourceKind::kDataset && dataset.groundTruth() && dataset.hasMasks()) {
    reference.emplace(dataset.camera(), config.frontend.min_mask_area_pct);
    recorder.useReferenceMasks(&*reference);
  }
  // Reads frame k and puts the configured masks on it (keeping the dataset's own when they are the reference).
  const auto read = [&](int k) {
    ImageFrame frame = dataset.read(k);
    if (reference && !frame.instance_ids.empty()) reference->keep(k, frame.instance_ids);
    ApplyMaskSource(config.masks, dataset.camera(), frame);
    return frame;
  };
  double read_s = 0.0;

  if (ours) {
    // Frames wait at most this many deep before each stage: enough to ride out a slow frame.
    constexpr size_t kQueueCapacity = 4;
    StagedPipelineCallbacks callbacks;
    callbacks.on_measurement = [&](const FrameMeasurement& m, const FrontendFrameStats& st, double ms) {
      recorder.record(m, st, ms);
    };
    const int step = std::max(1, frames / 10);
    StageLatency latency;
    callbacks.on_estimate = [&](const FrameEstimate& e, const FrameMeasurement&, const FrameTiming& timing) {
      FrameTiming t = timing;
      t.published_ns = SteadyClockNs();
      latency.add(t);
      if (progress && ((e.frame + 1) % step == 0 || e.frame + 1 == frames)) {
        std::lock_guard<std::mutex> lock(progress_mutex);
        *progress << "  ours: frame " << e.frame + 1 << "/" << frames << std::endl;
      }
    };
    StagedPipeline pipeline(config, dataset.camera(), dataset.frameRateHz(), kQueueCapacity, callbacks, stream);
    for (int k = 0; k < frames; ++k) {
      const int64_t received_ns = SteadyClockNs();
      ImageFrame frame = read(k);
      frame.timing.received_ns = received_ns;
      frame.timing.assembled_ns = SteadyClockNs();
      read_s += 1e-9 * static_cast<double>(frame.timing.assembled_ns - received_ns);
      if (!pipeline.push(std::move(frame))) break;  // a stage failed: finish() throws its error
    }
    *ours = pipeline.finish();
    recorder.setLatency(latency.summary());
  } else {
    FrontendParams frontend_params = config.frontend;
    frontend_params.frame_interval_s = 1.0 / dataset.frameRateHz();
    ImageFrontend frontend(frontend_params, dataset.camera());
    for (int k = 0; k < frames; ++k) {
      const auto t0 = Clock::now();
      ImageFrame frame = read(k);
      const auto t1 = Clock::now();
      const FrameMeasurement m = frontend.process(frame);
      read_s += std::chrono::duration<double>(t1 - t0).count();
      recorder.record(m, frontend.lastStats(), 1000.0 * SecondsSince(t1));
    }
  }

  ImageRunSummary s = recorder.summary(read_s);
  if (dataset.groundTruth()) {
    s.has_ground_truth = true;
    seq.gt = ToGroundTruth(*dataset.groundTruth(), frames, config.frontend.object_max_distance_m,
                           [&](int k, int id) { return recorder.visible(k, id); });
    if (reference) seq.gt.run_object_ids = reference->runObjectIds();
  }
  if (summary) *summary = s;
  return seq;
}

}  // namespace dslam
