// Issue 13's junction through the images: the simulator's `crossing` scenario rendered off-screen and
// run through the image front-end and ours, as `dslam render-scene --scenario crossing` and
// `dslam run` do. The crossing cars pass behind the stopped car ahead and enter and leave the 22 m
// range and the view; the oncoming ones grow as they come.
#include <gtest/gtest.h>

#include <filesystem>
#include <iostream>
#include <sstream>

#include "app/render_scene_command.h"
#include "evaluation/evaluate_run.h"
#include "pipeline/image_run.h"
#include "pipeline/run_sequence.h"
#include "simulation/scenarios.h"
#include "support/crossing_checks.h"
#include "support/no_display.h"
#include "pipeline/run_defaults.h"
#include "support/temp_paths.h"

namespace dslam {
namespace {
namespace fs = std::filesystem;

TEST(RenderedCrossing, CarsCrossingAndOncomingAreTrackedAndTheStopAndGoCarStandsOnlyWhileStopped) {
  const std::string dir = test::TempPath("rendered_crossing");
  test::ScopedNoDisplay no_display;  // render through our own Xvfb, as CI does
  RenderSceneOptions render;
  render.scenario = "crossing", render.out_dir = dir, render.quiet = true;
  std::ostringstream out, err;
  ASSERT_EQ(RunRenderSceneCommand(render, out, err), 0) << err.str();

  const RunConfig config = DefaultRunConfig(EntryPoint::kRun);
  const Sequence images = RunImageFrontend(ImageDataset(dir, config.dataset), config, 0, nullptr, nullptr);
  fs::remove_all(dir);
  RunSequenceOptions run;
  run.methods = {Method::kOurs};
  run.object_category = "VEHICLE";
  const Estimate ours = RunSequence(images, config, run).at(Method::kOurs).result.estimate;

  // Issue 13 asks 0.9 of each car's pairs. Those missed are where a car enters the view or the 22 m
  // range, or has fewer than 10 tracks for its first fit. A car leaving the view keeps the tracks of its
  // part still in it (ImageFrontend::retryNearPrediction); without that the 60 and 40 km/h cars fall to
  // 0.87 and 0.86.
  EXPECT_EQ(test::CheckJunctionTraffic(images, ours, 0.9), 6);

  // As in the simulated junction (CrossingScenario): stopped for the classifier's half-second window,
  // reported standing; moving again, reported moving; parked, never moving.
  test::CheckJunctionStopAndGoAndParked(images, ours, 20);
}

}  // namespace
}  // namespace dslam
