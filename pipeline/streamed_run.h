#pragma once
// A simulated run streamed end to end (`dslam sim`): frames made one at a time, the methods in lockstep
// (pipeline/lockstep_methods.h), each method's result files written (output/streaming_sink.h) and its
// metrics accumulated (evaluation/streaming_evaluator.h) as its estimates become final. Beyond the
// simulated world, which exists from the start, what it holds grows by a camera pose a frame per method,
// a stamp a frame and which frames saw each object: a few hundred bytes a frame.

#include <functional>
#include <ostream>
#include <string>
#include <vector>

#include "output/run_report.h"
#include "pipeline/run_config.h"
#include "simulation/sensor_simulator.h"

namespace dslam {

struct StreamedRunOptions {
  std::vector<Method> methods = {Method::kOurs, Method::kStaticOnly, Method::kSlamMot};
  std::string out_dir;               // created if needed
  std::ostream* progress = nullptr;  // progress lines; nullptr = quiet
  std::string object_category;       // object metrics over this category only (empty: all)
  std::function<void(int frames_done)> after_frame;  // e.g. to sample memory
};

struct StreamedRunResult {
  MethodOutcomes outcomes;  // metrics and wall times; the estimates are in the files, not here
  std::vector<ObjectSummary> ours_objects;
};

// Runs every frame of `simulator` and writes the result files of WriteRunOutputs except metrics.json
// (the caller's, with its run record). Throws std::runtime_error naming a file that cannot be written.
StreamedRunResult RunStreamed(SensorSimulator* simulator, const RunConfig& config, const StreamedRunOptions& options);

}  // namespace dslam
