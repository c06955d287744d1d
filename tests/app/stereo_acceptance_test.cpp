// Stereo depth on a scene rendered from KITTI 0003 with its right camera (skipped when ../shared/data is
// absent): with the shipped stereo configuration (config/kitti_stereo.yaml) the object speeds meet issue
// 34's targets for vehicles within 22 m, and weighing each point by its stereo depth noise beats weighing
// every point alike on the same depth.
#include <gtest/gtest.h>

#include <filesystem>
#include <iostream>
#include <sstream>

#include "app/render_scene_command.h"
#include "pipeline/config_yaml.h"
#include "pipeline/image_run.h"
#include "pipeline/run_sequence.h"
#include "support/no_display.h"
#include "support/run_defaults.h"
#include "support/temp_paths.h"

namespace dslam {
namespace {
namespace fs = std::filesystem;
const std::string kKitti = std::string(DSLAM_SHARED_DATA_DIR) + "/kitti_tracking";

MethodMetrics RunOurs(const std::string& dir, const RunConfig& config) {
  const Sequence images = RunImageFrontend(ImageDataset(dir, config.dataset), config, 0, nullptr, nullptr);
  RunSequenceOptions run;
  run.methods = {Method::kOurs};
  run.object_category = "VEHICLE";
  return RunSequence(images, config, run).at(Method::kOurs).metrics;
}

TEST(StereoRun, TheStereoConfigurationMeetsTheObjectTargetsAndItsDepthNoiseModelPays) {
  if (!fs::exists(kKitti + "/label_02/0003.txt")) GTEST_SKIP() << "shared data absent: " << kKitti;
  const std::string dir = test::TempPath("rendered_stereo_0003");
  test::ScopedNoDisplay no_display;
  RenderSceneOptions render;
  render.kitti_dir = kKitti, render.sequence = "0003", render.out_dir = dir, render.quiet = true;
  render.frames = 30, render.stereo = true;
  std::ostringstream out, err;
  ASSERT_EQ(RunRenderSceneCommand(render, out, err), 0) << err.str();

  const RunConfig shipped = LoadRunConfig(std::string(DSLAM_SOURCE_DIR) + "/config/kitti_stereo.yaml");
  RunConfig config = test::DslamRunDefaults();
  config.dataset = shipped.dataset;
  config.backend.noise = shipped.backend.noise;
  ASSERT_EQ(config.dataset.depth_encoding, "stereo");
  const MethodMetrics weighed = RunOurs(dir, config);
  config.backend.noise.point_sigma_per_depth_sq = 0.0;  // every point alike, as with exact depth
  const MethodMetrics flat = RunOurs(dir, config);
  fs::remove_all(dir);

  ASSERT_TRUE(weighed.objects && weighed.objects->omse_pct && weighed.camera.rte_pct);
  ASSERT_TRUE(flat.objects && flat.objects->omse_pct && flat.camera.rte_pct);
  std::cout << "stereo 0003, 30 frames: weighed RTE " << *weighed.camera.rte_pct << " %, OMSE "
            << *weighed.objects->omse_pct << " %, coverage " << *weighed.objects->object_coverage << "; flat RTE "
            << *flat.camera.rte_pct << " %, OMSE " << *flat.objects->omse_pct << " %" << std::endl;
  EXPECT_LT(*weighed.objects->omse_pct, 5.0);
  EXPECT_GE(*weighed.objects->object_coverage, 0.9);
  // Measured here: RTE 0.81 % against 1.29 %, OMSE 0.75 % against 1.04 %.
  EXPECT_LT(*weighed.camera.rte_pct, 0.85 * *flat.camera.rte_pct);
  EXPECT_LT(*weighed.objects->omse_pct, *flat.objects->omse_pct);
}

}  // namespace
}  // namespace dslam
