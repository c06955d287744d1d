#pragma once
// The run configuration `dslam run` uses when given no options (motion mode and schedule), for tests that
// run the image pipeline as a user would.

#include "app/run_command.h"
#include "pipeline/run_config.h"

namespace dslam::test {

inline RunConfig DslamRunDefaults() {
  RunConfig config;
  config.backend.default_mode = ParseMotionMode(kRunDefaultMode);
  config.backend.schedule = ParseSchedule(RunCommandOptions().default_schedule.value());
  return config;
}

}  // namespace dslam::test
