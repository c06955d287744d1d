// Thirty frames rendered from KITTI 0003 with the right camera (skipped when ../shared/data is absent),
// rendered once for the suite:
// - stereo depth: with the shipped stereo configuration (config/kitti_stereo.yaml) the object speeds meet
//   issue 34's targets for vehicles within 22 m, and weighing each point by its stereo depth noise beats
//   weighing every point alike on the same depth;
// - masks made from a LiDAR scan sampled from the depth: the run's own object ids are matched to the ground
//   truth by where its points fall in the exact masks, and the object speeds meet the targets.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <map>
#include <set>
#include <sstream>
#include <utility>

#include "app/render_scene_command.h"
#include "pipeline/config_yaml.h"
#include "pipeline/image_run.h"
#include "pipeline/run_sequence.h"
#include "support/shared_data.h"
#include "support/no_display.h"
#include "pipeline/run_defaults.h"
#include "support/temp_paths.h"

namespace dslam {
namespace {
namespace fs = std::filesystem;

class ShortRenderedKitti : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (!fs::exists(test::KittiTrackingDir() + "/label_02/0003.txt")) return;
    dir_ = new std::string(test::TempPath("rendered_stereo_0003"));
    test::ScopedNoDisplay no_display;
    RenderSceneOptions render;
    render.kitti_dir = test::KittiTrackingDir(), render.sequence = "0003", render.out_dir = *dir_, render.quiet = true;
    render.frames = 30, render.stereo = true;
    std::ostringstream out, err;
    if (RunRenderSceneCommand(render, out, err) != 0) {
      std::cerr << "render-scene failed: " << err.str() << std::endl;
      fs::remove_all(*dir_);
      delete dir_;
      dir_ = nullptr;
    }
  }
  static void TearDownTestSuite() {
    if (dir_) fs::remove_all(*dir_);
    delete dir_;
    dir_ = nullptr;
  }
  void SetUp() override {
    if (!fs::exists(test::KittiTrackingDir() + "/label_02/0003.txt")) GTEST_SKIP() << "shared data absent: " << test::KittiTrackingDir();
    ASSERT_NE(dir_, nullptr) << "the scene could not be rendered";
  }
  static MethodMetrics RunOurs(const RunConfig& config, Sequence* images_out = nullptr) {
    Sequence images = RunImageFrontend(ImageDataset(*dir_, config.dataset), config, 0, nullptr, nullptr);
    RunSequenceOptions run;
    run.methods = {Method::kOurs};
    run.object_category = "VEHICLE";
    MethodMetrics metrics = RunSequence(images, config, run).at(Method::kOurs).metrics;
    if (images_out) *images_out = std::move(images);
    return metrics;
  }
  static std::string* dir_;
};
std::string* ShortRenderedKitti::dir_ = nullptr;

TEST_F(ShortRenderedKitti, TheStereoConfigurationMeetsTheObjectTargetsAndItsDepthNoiseModelPays) {
  const RunConfig shipped = LoadRunConfig(std::string(DSLAM_SOURCE_DIR) + "/config/kitti_stereo.yaml");
  RunConfig config = DefaultRunConfig(EntryPoint::kRun);
  config.dataset = shipped.dataset;
  config.backend.noise = shipped.backend.noise;
  ASSERT_EQ(config.dataset.depth_encoding, "stereo");
  const MethodMetrics weighed = RunOurs(config);
  config.backend.noise.point_sigma_per_depth_sq = 0.0;  // every point alike, as with exact depth
  const MethodMetrics flat = RunOurs(config);

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

TEST_F(ShortRenderedKitti, MasksFromTheLidarAreMatchedToTheTruthAndMeetTheObjectTargets) {
  RunConfig config = DefaultRunConfig(EntryPoint::kRun);
  config.frontend.association.mask_ids_tracked = false;
  config.masks.source = MaskSourceKind::kLidarClusters;
  config.masks.lidar_from_depth = true;
  Sequence images;
  const MethodMetrics m = RunOurs(config, &images);
  ASSERT_TRUE(images.gt.run_object_ids.has_value());
  // The car ahead, in view throughout, is found under one of the run's ids in nearly every frame, and no
  // run object is two ground-truth objects in one frame.
  std::map<int, int> frames_found;
  std::set<std::pair<int, int>> run_ids_in_frame;
  for (const auto& [key, run_id] : *images.gt.run_object_ids) {
    ++frames_found[key.second];
    EXPECT_TRUE(run_ids_in_frame.insert({key.first, run_id}).second) << "frame " << key.first << ", run id " << run_id;
  }
  int most_frames = 0;
  for (const auto& [gt_id, frames] : frames_found) most_frames = std::max(most_frames, frames);
  EXPECT_GE(most_frames, 27);
  ASSERT_TRUE(m.objects && m.objects->omse_pct && m.objects->object_coverage);
  std::cout << "LiDAR masks, 0003, 30 frames: OMSE " << *m.objects->omse_pct << " %, coverage "
            << *m.objects->object_coverage << std::endl;
  // Measured here: OMSE 0.40 %, coverage 0.97.
  EXPECT_LT(*m.objects->omse_pct, 5.0);
  EXPECT_GE(*m.objects->object_coverage, 0.8);
  // No static pair called dynamic (0003 has none in these frames; when it has, none may be).
  EXPECT_EQ(m.objects->static_false_dynamic_frac.value_or(0.0), 0.0);
}

}  // namespace
}  // namespace dslam
