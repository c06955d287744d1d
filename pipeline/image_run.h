#pragma once
// Runs the image front-end over a recorded image dataset, frame by frame, into the sequence of
// measurements the back-end consumes (with the dataset's ground truth, when it has some, gated as the
// front-end gates objects).

#include <ostream>

#include "data/image_dataset.h"
#include "data/sequence.h"
#include "frontend/image_frontend.h"
#include "backend/methods.h"
#include "output/streaming_sink.h"
#include "pipeline/run_config.h"
#include "pipeline/stage_latency.h"

namespace dslam {

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
  // With ours online: the latency of each stage (pipeline/stage_latency.h; "input" is reading the files
  // and making masks, "publish" handing the estimate on).
  std::vector<StageLatencySummary> latency;
};

// max_frames <= 0: the whole dataset. Throws std::runtime_error naming the frame and file on bad input.
// `frame_log`, when given, receives one CSV row per frame and object (object_id 0: the background, flowed -1):
// frame,object_id,flowed,tracked,added,measured,motion_rejected,pnp_inliers,median_fb_px,odometry_rejected,
// previous,survival,reacquired
// (see FrontendFrameStats::ObjectCounts).
// With `ours`, the stages run in parallel (pipeline/staged_pipeline.h): this thread reads and decodes the
// files, the front-end and ours' back-end each run on their own thread, and `ours` receives ours' result
// (the same as RunSequence computes from the returned measurements), and `stream`, when given, ours' result
// files as the estimates become final (output/streaming_sink.h). Without `ours`, the front-end runs here.
Sequence RunImageFrontend(const ImageDataset& dataset, const RunConfig& config, int max_frames, std::ostream* progress,
                          ImageRunSummary* summary, std::ostream* frame_log = nullptr, MethodResult* ours = nullptr,
                          StreamingFileSink* stream = nullptr);

}  // namespace dslam
