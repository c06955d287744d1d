#pragma once
// Runs a recorded image dataset: the image front-end frame by frame, alone (into the sequence of
// measurements the back-end consumes) or streamed with the methods behind it (`dslam run`).

#include <functional>
#include <map>
#include <ostream>
#include <set>
#include <string>
#include <vector>

#include "data/image_dataset.h"
#include "data/sequence.h"
#include "frontend/image_frontend.h"
#include "backend/methods.h"
#include "output/run_report.h"
#include "pipeline/run_config.h"
#include "pipeline/stage_latency.h"

namespace dslam {

// A frame's image and instance masks, kept beyond the stream.
struct KeptFrame {
  cv::Mat image;
  cv::Mat instance_ids;
};

struct ImageRunSummary {
  int frames = 0;
  double frontend_ms_per_frame = 0.0;  // front-end only (excludes reading the files)
  double read_ms_per_frame = 0.0;
  double mean_static_tracks = 0.0;     // static points per frame (tracked + new)
  double mean_object_points = 0.0;
  double mean_pnp_inliers = 0.0;
  int odometry_rejected = 0;           // frames whose odometry contradicted the PnP motion (dropped)
  double median_fb_error_px = 0.0;     // median over frames of each frame's median
  bool has_ground_truth = false;
  // Streamed with ours: the latency of each stage (pipeline/stage_latency.h; "input" is reading the files
  // and making masks, "publish" handing the estimate on).
  std::vector<StageLatencySummary> latency;
};

// The front-end alone over the dataset, on this thread: the measurements, with the dataset's ground truth
// gated as the front-end gates objects (what tests and studies feed RunSequence). max_frames <= 0: the
// whole dataset. Throws std::runtime_error naming the frame and file on bad input.
// `frame_log`, when given, receives one CSV row per frame and object (object_id 0: the background, flowed -1):
// frame,object_id,flowed,tracked,added,measured,motion_rejected,pnp_inliers,median_fb_px,odometry_rejected,
// previous,survival,reacquired
// (see FrontendFrameStats::ObjectCounts).
Sequence RunImageFrontend(const ImageDataset& dataset, const RunConfig& config, int max_frames, std::ostream* progress,
                          ImageRunSummary* summary, std::ostream* frame_log = nullptr);

// The frames a run of at most `max_frames` (<= 0: no limit) takes of the dataset.
int FramesToRun(const ImageDataset& dataset, int max_frames);

struct ImageRunOptions {
  std::vector<Method> methods = {Method::kOurs, Method::kStaticOnly, Method::kSlamMot};
  int max_frames = 0;                // <= 0: the whole dataset
  std::string out_dir;               // the result files, written as the estimates become final; empty: none
  std::ostream* progress = nullptr;  // progress lines; nullptr = quiet
  std::ostream* frame_log = nullptr; // as RunImageFrontend's
  std::string object_category;       // object metrics over this category only (empty: all)
  // Frames whose image and masks (as the front-end saw them) and ours' final object motions the result
  // keeps: the report's overlays are drawn from them without reading those frames again.
  std::set<int> keep_frames;
  // Replay the dataset forwards and backwards in turn (data/ping_pong_replay.h) for max_frames frames: a
  // long run from a short recording, for memory benchmarks; nothing is evaluated.
  bool ping_pong = false;
  // Called on the reading thread after each frame is handed to the front-end, with the frames read so far.
  std::function<void(int)> after_frame;
};

struct ImageRunResult {
  ImageRunSummary summary;
  MethodOutcomes outcomes;  // metrics (with ground truth) and wall times; the estimates are in the files
  std::vector<ObjectSummary> ours_objects;            // with ground truth
  std::vector<ObjectMotionEstimate> kept_motions;     // ours', of the frames in keep_frames
  std::map<int, KeptFrame> kept_frames;               // the frames in keep_frames that were run
  // Why the run stopped before the last frame (a frame that could not be read: the error, naming the file);
  // empty when it ran to the end. The frames before it are estimated and their files written whole.
  std::string stopped_by;
};

// `dslam run`'s one stream: this thread reads and decodes the files, the front-end runs on its own thread
// and the back-end on another, with the methods in lockstep (pipeline/lockstep_methods.h); each method's
// result files (WriteRunOutputs' layout except metrics.json, which is the caller's) and evaluation grow
// as its estimates become final. What it holds beyond the window grows by a stamp and a camera pose a
// frame per method. Its metrics equal RunSequence's on RunImageFrontend's measurements.
ImageRunResult RunImageStreamed(const ImageDataset& dataset, const RunConfig& config, const ImageRunOptions& options);

}  // namespace dslam
