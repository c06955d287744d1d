#include "app/sim_command.h"

#include <chrono>
#include <exception>

#include "pipeline/config_yaml.h"
#include "pipeline/run_sequence.h"
#include "simulation/scenarios.h"

namespace dslam {

int RunSimCommand(const SimCommandOptions& options, std::ostream& out, std::ostream& err) {
  try {
    const auto start = std::chrono::steady_clock::now();
    RunConfig config = options.config_path ? LoadRunConfig(*options.config_path) : RunConfig{};
    config.backend.default_mode = ParseMotionMode(options.mode.value_or(ScenarioDefaultMotionMode(options.scenario)));
    if (options.schedule) config.backend.schedule = ParseSchedule(*options.schedule);
    if (!(options.sigma_m > 0.0)) throw std::invalid_argument("--sigma must be positive");
    config.backend.noise.point_sigma_m = options.sigma_m;
    config.validate();

    ScenarioOptions scenario;
    scenario.seed = options.seed;
    scenario.num_frames = options.frames;
    scenario.noise.point_sigma_m = options.sigma_m;
    const Sequence seq = MakeScenario(options.scenario, scenario);
    if (!options.quiet)
      out << "Simulated '" << seq.name << "': " << seq.frames.size() << " frames, " << seq.gt.objects.size()
          << " objects, seed " << options.seed << std::endl;

    RunSequenceOptions run;
    run.progress = options.quiet ? nullptr : &out;
    const MethodOutcomes outcomes = RunSequence(seq, config, run);

    nlohmann::json info;
    info["command"] = "sim";
    info["scenario"] = options.scenario;
    info["seed"] = options.seed;
    info["frames"] = seq.frames.size();
    info["sigma_m"] = options.sigma_m;
    info["mode"] = ToString(config.backend.default_mode);
    info["schedule"] = ToString(config.backend.schedule);
    info["config"] = options.config_path.value_or("");
    info["wall_time_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    WriteRunOutputs(options.out_dir, seq, outcomes, info);

    out << FormatMetricsTable(outcomes, "Scenario " + options.scenario + " (seed " + std::to_string(options.seed) +
                                            ", mode " + ToString(config.backend.default_mode) + ", " +
                                            ToString(config.backend.schedule) + ")");
    out << "Results written to " << options.out_dir << std::endl;
    return 0;
  } catch (const std::exception& e) {
    err << "dslam sim: error: " << e.what() << std::endl;
    return 2;
  }
}

}  // namespace dslam
