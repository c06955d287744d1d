// The image front-end on scenes rendered from KITTI 0000, 0003 and 0005 (skipped when ../shared/data is
// absent): what issue 6 asks of `dslam run` - OMSE below 10 % and object coverage of at least 80 % for
// vehicles within 22 m, and camera RTE within twice that of the ground-truth replay of the same sequence.
#include <gtest/gtest.h>

#include <filesystem>
#include <iostream>
#include <sstream>

#include "app/kitti_replay_command.h"
#include "app/render_scene_command.h"
#include "app/run_command.h"
#include "data/kitti_dataset.h"
#include "pipeline/image_run.h"
#include "pipeline/run_sequence.h"
#include "simulation/kitti_replay.h"
#include "support/shared_data.h"
#include "support/no_display.h"
#include "pipeline/run_defaults.h"
#include "support/temp_paths.h"

namespace dslam {
namespace {
namespace fs = std::filesystem;

class RenderedKittiSequence : public ::testing::TestWithParam<std::string> {};

TEST_P(RenderedKittiSequence, ImagePipelineMeetsTheTargetsOnVehicles) {
  if (!fs::exists(test::KittiTrackingDir() + "/label_02/0000.txt")) GTEST_SKIP() << "shared data absent: " << test::KittiTrackingDir();
  const std::string seq = GetParam();
  const std::string dir = test::TempPath("rendered_" + seq);
  test::ScopedNoDisplay no_display;  // render through our own Xvfb, as CI does
  RenderSceneOptions render;
  render.kitti_dir = test::KittiTrackingDir(), render.sequence = seq, render.out_dir = dir, render.quiet = true;
  std::ostringstream out, err;
  ASSERT_EQ(RunRenderSceneCommand(render, out, err), 0) << err.str();

  const RunConfig config = DefaultRunConfig(EntryPoint::kRun);
  ImageRunSummary summary;
  const Sequence images = RunImageFrontend(ImageDataset(dir, config.dataset), config, 0, nullptr, &summary);
  fs::remove_all(dir);
  RunSequenceOptions run;
  run.methods = {Method::kOurs};
  run.object_category = "VEHICLE";
  const MethodMetrics image_metrics = RunSequence(images, config, run).at(Method::kOurs).metrics;

  RunConfig replay_config;
  replay_config.backend.default_mode = DefaultsOf(EntryPoint::kKittiReplay).mode;
  const Sequence replay = MakeKittiReplay(LoadKittiGroundTruth(test::KittiTrackingDir(), seq), KittiReplayOptions{});
  const MethodMetrics replay_metrics = RunSequence(replay, replay_config, run).at(Method::kOurs).metrics;

  ASSERT_TRUE(image_metrics.objects && image_metrics.objects->omse_pct && image_metrics.camera.rte_pct);
  const auto& o = *image_metrics.objects;
  std::cout << "| " << seq << " | " << images.frames.size() << " | " << summary.frontend_ms_per_frame << " | "
            << *o.omse_pct << " % | " << (o.omte_pct ? *o.omte_pct : -1.0) << " % | " << *o.object_coverage << " | "
            << *image_metrics.camera.rte_pct << " % | " << *replay_metrics.camera.rte_pct << " % |" << std::endl;
  // The speeds a vehicle acts on: within 3 % on the whole, for at least 95 % of the frame pairs of vehicles
  // within 22 m (0000 is at 2.65 % and 0.959: its parked cars' pairs whose label jitter counts as moving).
  EXPECT_LT(*o.omse_pct, 3.0);
  EXPECT_GE(*o.object_coverage, 0.95);
  EXPECT_LE(*image_metrics.camera.rte_pct, 2.0 * *replay_metrics.camera.rte_pct);
}

INSTANTIATE_TEST_SUITE_P(SharedSequences, RenderedKittiSequence, ::testing::Values("0000", "0003", "0005"));

}  // namespace
}  // namespace dslam
