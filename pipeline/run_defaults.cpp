#include "pipeline/run_defaults.h"

#include "simulation/scenarios.h"

namespace dslam {

RunDefaults DefaultsOf(EntryPoint entry, const std::string& scenario) {
  RunDefaults d;
  switch (entry) {
    case EntryPoint::kRun:
    case EntryPoint::kStudy:
    case EntryPoint::kServe:
      // Image runs carry hundreds of points a frame: the window keeps them fast (and serve must be online).
      d.mode = MotionMode::kSmoothed;
      d.schedule = {ScheduleKind::kSlidingWindow, 10};
      break;
    case EntryPoint::kSim:
      d.mode = ParseMotionMode(ScenarioDefaultMotionMode(scenario));
      d.schedule = {ScheduleKind::kBatch, 10};
      break;
    case EntryPoint::kKittiReplay:
      d.mode = MotionMode::kSmoothed;
      d.schedule = {ScheduleKind::kBatch, 10};
      break;
  }
  return d;
}

RunConfig DefaultRunConfig(EntryPoint entry, const std::string& scenario) {
  const RunDefaults d = DefaultsOf(entry, scenario);
  RunConfig config;
  config.backend.default_mode = d.mode;
  config.backend.schedule = d.schedule;
  return config;
}

}  // namespace dslam
