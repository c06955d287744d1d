#include "app/run_command.h"

#include <algorithm>
#include <cstdio>
#include <chrono>
#include <exception>
#include <fstream>
#include <future>
#include <map>
#include <sstream>

#include "output/frame_overlay.h"
#include "output/object_summary.h"
#include "output/run_report.h"
#include "output/whole_line_file.h"
#include "pipeline/image_run.h"

namespace dslam {
namespace {

// A few frames with each object's mask, id and speed drawn on them (frame_NNNNNN.png), for the report: drawn
// from the frames the stream kept, one thread each (the run's last serial step; each PNG takes tens of ms).
void WriteFrameOverlays(const std::map<int, KeptFrame>& frames, const std::vector<ObjectMotionEstimate>& motions,
                        const std::string& dir) {
  std::vector<std::future<void>> writing;
  for (const auto& [k, frame] : frames)
    writing.push_back(std::async(std::launch::async, [&, k = k] {
      std::vector<ObjectMotionEstimate> here;
      for (const ObjectMotionEstimate& m : motions)
        if (m.frame == k) here.push_back(m);
      char name[32];
      std::snprintf(name, sizeof name, "/frame_%06d.png", k);
      WriteOverlayPng(DrawObjectOverlay(frame.image, frame.instance_ids, here), dir + name);
    }));
  for (auto& w : writing) w.get();  // throws the first error; the other futures wait for their writes
}

}  // namespace

int RunRunCommand(const RunCommandOptions& options, std::ostream& out, std::ostream& err) {
  try {
    const auto start = std::chrono::steady_clock::now();
    RunConfig config = BuildRunConfig(options, EntryPoint::kRun);
    if (options.flow) config.frontend.flow.method = ParseFlowMethod(*options.flow);
    if (options.frames < 0) throw std::invalid_argument("--frames must be >= 0");
    RequireWritableOutDir(options.out_dir);
    ImageDatasetOptions dataset_options = config.dataset;
    dataset_options.sequence = options.sequence;
    // Only the precomputed flow method reads flow/*.flo: another must not fail on a file it never uses.
    dataset_options.read_flow = config.frontend.flow.method == FlowMethod::kPrecomputed;
    const ImageDataset dataset(options.dataset_dir, dataset_options);
    if (config.frontend.flow.method == FlowMethod::kPrecomputed && !dataset.hasFlow())
      throw std::invalid_argument(options.dataset_dir + " has no flow/ folder for flow method 'precomputed'");
    if (!options.quiet)
      out << "Dataset " << options.dataset_dir << " (" << dataset.layout() << "): " << dataset.size() << " frames "
          << dataset.camera().width << "x" << dataset.camera().height << ", masks " << (dataset.hasMasks() ? "yes" : "no")
          << ", odometry " << (dataset.hasOdometry() ? "yes" : "no") << ", ground truth "
          << (dataset.groundTruth() ? "yes" : "no") << "; flow " << ToString(config.frontend.flow.method) << "; "
          << dataset.frameRateHz() << " Hz (" << dataset.frameRateSource() << ")" << std::endl;
    for (const std::string& warning : dataset.warnings()) err << "dslam run: warning: " << warning << std::endl;

    const std::string log_path = options.out_dir + "/frontend.csv";
    WholeLineFile frame_log(log_path);  // whole rows on disk whatever ends the run
    if (!frame_log) throw std::runtime_error("cannot write " + log_path);
    ImageRunOptions run;
    run.max_frames = options.frames;
    run.out_dir = options.out_dir;
    run.progress = options.quiet ? nullptr : &out;
    run.frame_log = &frame_log;
    run.object_category = options.category;
    run.methods.clear();
    for (Method m : {Method::kOurs, Method::kStaticOnly, Method::kSlamMot})
      if (std::find(options.methods.begin(), options.methods.end(), ToString(m)) != options.methods.end())
        run.methods.push_back(m);
    if (run.methods.empty()) throw std::invalid_argument("--methods names no method (ours, static_only, slam_mot)");
    const bool with_ours = std::find(run.methods.begin(), run.methods.end(), Method::kOurs) != run.methods.end();
    const int frames = FramesToRun(dataset, options.frames);
    const bool overlays = with_ours && (dataset.hasMasks() || config.masks.source != MaskSourceKind::kDataset);
    if (overlays)
      for (int k : OverlayFrames(frames, 4)) run.keep_frames.insert(k);

    // One stream: the front-end and the methods (ours and the baselines in lockstep) run in parallel; the
    // result files grow as the estimates become final (a crash loses only the window), and the metrics
    // are summed as they do.
    const ImageRunResult result = RunImageStreamed(dataset, config, run);
    const ImageRunSummary& summary = result.summary;
    const MethodOutcomes& outcomes = result.outcomes;

    nlohmann::json info = RunInfo("run", options, config);
    info["dataset"] = options.dataset_dir;
    info["layout"] = dataset.layout();
    info["frames"] = summary.frames;
    info["frame_rate_hz"] = dataset.frameRateHz();  // what speeds were measured at, and from where
    info["frame_rate_source"] = dataset.frameRateSource();
    info["flow_method"] = ToString(config.frontend.flow.method);
    info["object_category"] = options.category;
    info["object_max_distance_m"] = config.frontend.object_max_distance_m;
    info["frontend"] = {{"ms_per_frame", summary.frontend_ms_per_frame},
                        {"read_ms_per_frame", summary.read_ms_per_frame},
                        {"mean_static_points", summary.mean_static_tracks},
                        {"mean_object_points", summary.mean_object_points},
                        {"mean_pnp_inliers", summary.mean_pnp_inliers},
                        {"odometry_rejected_frames", summary.odometry_rejected},
                        {"median_fb_error_px", summary.median_fb_error_px}};
    if (!summary.latency.empty()) info["latency_ms"] = LatencyJson(summary.latency);
    if (!result.stopped_by.empty()) info["stopped_by"] = result.stopped_by;
    info["wall_time_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    WriteMetricsJson(options.out_dir, outcomes, info);
    if (overlays) WriteFrameOverlays(result.kept_frames, result.kept_motions, options.out_dir);

    std::ostringstream discarded;  // --quiet: only errors
    std::ostream& report = options.quiet ? discarded : out;
    report << "Front-end: " << summary.frontend_ms_per_frame << " ms/frame (reading " << summary.read_ms_per_frame
        << " ms/frame), " << summary.mean_static_tracks << " static and " << summary.mean_object_points
        << " object points per frame, " << summary.mean_pnp_inliers << " PnP inliers, median forward-backward error "
        << summary.median_fb_error_px << " px" << std::endl;
    if (!summary.latency.empty())
      report << "Latency per stage, ms (median/p99): " << FormatLatencyLine(summary.latency) << std::endl;
    if (summary.odometry_rejected > 0)
      report << "Odometry dropped on " << summary.odometry_rejected
          << " frame(s): it contradicted the camera motion the static points gave (frontend.csv column odometry_rejected)"
          << std::endl;
    if (summary.has_ground_truth) {
      const std::string what = options.category.empty() ? "all objects" : options.category + " objects";
      report << FormatMetricsTable(outcomes, "Image run on " + dataset.name() + " (" + what + " within " +
                                              std::to_string(static_cast<int>(config.frontend.object_max_distance_m)) +
                                              " m, mode " + ToString(config.backend.default_mode) + ")");
      if (outcomes.count(Method::kOurs))
        report << FormatObjectTable(result.ours_objects, "Per object (ours)");
    } else {
      report << "No ground truth in " << options.dataset_dir << ": estimates written without metrics" << std::endl;
    }
    report << "Results written to " << options.out_dir << std::endl;
    const int figures = DrawRunFigures(options, out, err);
    if (!result.stopped_by.empty()) {
      err << "dslam run: error: " << result.stopped_by << " (the run stopped there; the " << summary.frames
          << " frames before it were estimated and written to " << options.out_dir << ")" << std::endl;
      return 2;
    }
    return figures;
  } catch (const std::exception& e) {
    err << "dslam run: error: " << e.what() << std::endl;
    return 2;
  }
}

}  // namespace dslam
