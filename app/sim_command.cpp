#include "app/sim_command.h"

#include <chrono>
#include <exception>

#include "pipeline/streamed_run.h"
#include "simulation/scenarios.h"

namespace dslam {

int RunSimCommand(const SimCommandOptions& options, std::ostream& out, std::ostream& err) {
  try {
    const auto start = std::chrono::steady_clock::now();
    const RunConfig config = BuildRunConfig(options, EntryPoint::kSim, options.scenario);

    ScenarioOptions scenario;
    scenario.seed = options.seed;
    scenario.num_frames = options.frames;
    scenario.noise.point_sigma_m = options.sigma_m;
    SensorSimulator simulator = MakeScenarioSimulator(options.scenario, scenario);
    RequireWritableOutDir(options.out_dir);  // before the methods run, not after
    if (!options.quiet)
      out << "Simulating '" << simulator.name() << "': " << simulator.numFrames() << " frames, "
          << simulator.groundTruth().objects.size() << " objects, seed " << options.seed
          << "; the three methods side by side, results written as they become final" << std::endl;

    // Frame by frame: a long simulation holds the smoothers' windows, not its frames.
    StreamedRunOptions run;
    run.out_dir = options.out_dir;
    run.progress = options.quiet ? nullptr : &out;
    const MethodOutcomes outcomes = RunStreamed(&simulator, config, run).outcomes;

    nlohmann::json info = RunInfo("sim", options, config);
    info["scenario"] = options.scenario;
    info["frames"] = simulator.numFrames();
    info["wall_time_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    WriteMetricsJson(options.out_dir, outcomes, info);

    out << FormatMetricsTable(outcomes, "Scenario " + options.scenario + " (seed " + std::to_string(options.seed) +
                                            ", mode " + ToString(config.backend.default_mode) + ", " +
                                            ToString(config.backend.schedule) + ")");
    out << "Results written to " << options.out_dir << std::endl;
    return DrawRunFigures(options, out, err);
  } catch (const std::exception& e) {
    err << "dslam sim: error: " << e.what() << std::endl;
    return 2;
  }
}

}  // namespace dslam
