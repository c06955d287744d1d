#include "app/kitti_replay_command.h"

#include <chrono>
#include <exception>

#include "data/kitti_dataset.h"
#include "output/object_summary.h"
#include "pipeline/streamed_run.h"
#include "simulation/kitti_replay.h"

namespace dslam {

int RunKittiReplayCommand(const KittiReplayCommandOptions& options, std::ostream& out, std::ostream& err) {
  try {
    const auto start = std::chrono::steady_clock::now();
    const RunConfig config = BuildRunConfig(options, EntryPoint::kKittiReplay);
    RequireWritableOutDir(options.out_dir);
    const KittiGroundTruthSequence gt = LoadKittiGroundTruth(options.data_dir, options.sequence);

    KittiReplayOptions replay;
    replay.seed = options.seed;
    replay.noise.point_sigma_m = options.sigma_m;
    SensorSimulator simulator = MakeKittiReplaySimulator(gt, replay);
    if (!options.quiet)
      out << "KITTI " << options.sequence << ": " << simulator.numFrames() << " frames, "
          << simulator.groundTruth().objects.size() << " labelled objects, replay sigma " << options.sigma_m
          << " m, seed " << options.seed << std::endl;

    StreamedRunOptions run;
    run.out_dir = options.out_dir;
    run.progress = options.quiet ? nullptr : &out;
    run.object_category = options.category;
    const StreamedRunResult result = RunStreamed(&simulator, config, run);
    const MethodOutcomes& outcomes = result.outcomes;

    nlohmann::json info = RunInfo("kitti-replay", options, config);
    info["data"] = options.data_dir;
    info["sequence"] = options.sequence;
    info["frames"] = simulator.numFrames();
    info["object_category"] = options.category;
    info["object_max_range_m"] = replay.object_max_range_m;
    info["sources"] = gt.sources;
    info["wall_time_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    WriteMetricsJson(options.out_dir, outcomes, info);

    const std::string what = options.category.empty() ? "all objects" : options.category + " objects";
    out << FormatMetricsTable(outcomes, "KITTI " + options.sequence + " ground-truth replay (" + what + " within " +
                                            std::to_string(static_cast<int>(replay.object_max_range_m)) + " m, mode " +
                                            ToString(config.backend.default_mode) + ")");
    out << FormatObjectTable(result.ours_objects, "Per object (ours)");
    out << "Results written to " << options.out_dir << std::endl;
    return DrawRunFigures(options, out, err);
  } catch (const std::exception& e) {
    err << "dslam kitti-replay: error: " << e.what() << std::endl;
    return 2;
  }
}

}  // namespace dslam
