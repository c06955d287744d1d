#pragma once
// Every entry point's defaults in one place: the motion model and the solver schedule each command starts
// from, under the configuration file and the flags (app/run_setup.h; the order is in docs/configuration.md).
//
//   entry point             motion model                           schedule
//   run, study, serve       smoothed                               window:10 (hundreds of points a frame)
//   sim                     the scenario's (constant for paper,    batch
//                           smoothed for city and crossing)
//   kitti-replay            smoothed                               batch
//
// `serve` estimates online and refuses batch (an offline schedule) whatever sets it.

#include <string>

#include "backend/backend_params.h"
#include "pipeline/run_config.h"

namespace dslam {

enum class EntryPoint { kRun, kStudy, kServe, kSim, kKittiReplay };

struct RunDefaults {
  MotionMode mode = MotionMode::kSmoothed;
  Schedule schedule;
};

// `scenario`: sim's scenario (ignored elsewhere).
RunDefaults DefaultsOf(EntryPoint entry, const std::string& scenario = "");
// The built-in configuration with the entry point's defaults applied.
RunConfig DefaultRunConfig(EntryPoint entry, const std::string& scenario = "");

}  // namespace dslam
