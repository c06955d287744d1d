#include "pipeline/config_yaml.h"

#include <gtest/gtest.h>

namespace dslam {
namespace {

TEST(ConfigYaml, RoundTripKeepsEveryValue) {
  RunConfig c;
  c.backend.default_mode = MotionMode::kSmoothed;
  c.backend.slam_mot_mode = MotionMode::kConstant;
  c.backend.schedule = {ScheduleKind::kSlidingWindow, 7};
  c.backend.noise.point_sigma_m = 0.037;
  c.backend.noise.motion_sigma_m = 0.0123;
  c.backend.noise.huber_delta = 1.5;
  c.backend.noise.smoothness_huber_delta = 0.75;
  c.backend.noise.smoothness_from_residuals = false;
  c.backend.motion_ransac.inlier_threshold_m = 0.21;
  c.backend.object_window_frames = 4;
  c.backend.landmark_history_frames = 12;
  c.backend.batch_function_tolerance = 3e-9;
  c.backend.mode_per_object[4] = MotionMode::kConstant;
  c.classifier.dynamic_speed_threshold_mps = 0.8;
  c.classifier.report_speed_threshold_mps = 1.3;
  c.classifier.min_static_transitions = 3;
  c.classifier.small_object_area_pct = 1.5;
  c.backend.linear_solver = LinearSolver::kSchur;
  c.backend.marginalisation = Marginalisation::kExact;
  c.frontend.warped_search.radius_px = 31;
  c.frontend.warped_search.min_ncc = 0.9;
  c.frontend.warped_search.min_deformation = 0.2;
  c.frontend.warped_search.max_flow_deformation = 0.7;
  const RunConfig back = ParseRunConfig(RunConfigToYaml(c));
  EXPECT_EQ(back.backend.default_mode, MotionMode::kSmoothed);
  EXPECT_EQ(back.backend.slam_mot_mode, MotionMode::kConstant);
  EXPECT_EQ(back.backend.schedule.kind, ScheduleKind::kSlidingWindow);
  EXPECT_EQ(back.backend.schedule.window_frames, 7);
  EXPECT_EQ(back.backend.noise.point_sigma_m, 0.037);
  EXPECT_EQ(back.backend.noise.motion_sigma_m, 0.0123);
  EXPECT_EQ(back.backend.noise.huber_delta, 1.5);
  EXPECT_EQ(back.backend.noise.smoothness_huber_delta, 0.75);
  EXPECT_FALSE(back.backend.noise.smoothness_from_residuals);
  EXPECT_EQ(back.backend.motion_ransac.inlier_threshold_m, 0.21);
  EXPECT_EQ(back.backend.object_window_frames, 4);
  EXPECT_EQ(back.backend.landmark_history_frames, 12);
  EXPECT_EQ(back.backend.batch_function_tolerance, 3e-9);
  EXPECT_EQ(back.backend.modeFor(4), MotionMode::kConstant);
  EXPECT_EQ(back.classifier.dynamic_speed_threshold_mps, 0.8);
  EXPECT_EQ(back.classifier.report_speed_threshold_mps, 1.3);
  EXPECT_EQ(back.classifier.min_static_transitions, 3);
  EXPECT_EQ(back.classifier.small_object_area_pct, 1.5);
  EXPECT_EQ(back.backend.linear_solver, LinearSolver::kSchur);
  EXPECT_EQ(back.backend.marginalisation, Marginalisation::kExact);
  EXPECT_EQ(back.frontend.warped_search.radius_px, 31);
  EXPECT_EQ(back.frontend.warped_search.min_ncc, 0.9);
  EXPECT_EQ(back.frontend.warped_search.min_deformation, 0.2);
  EXPECT_EQ(back.frontend.warped_search.max_flow_deformation, 0.7);
  EXPECT_EQ(RunConfigToYaml(back), RunConfigToYaml(c));
}

TEST(ConfigYaml, ShippedDefaultFileEqualsBuiltInDefaults) {
  const RunConfig file = LoadRunConfig(std::string(DSLAM_SOURCE_DIR) + "/config/default.yaml");
  EXPECT_EQ(RunConfigToYaml(file), RunConfigToYaml(RunConfig{}));
}

TEST(ConfigYaml, EmptyDocumentGivesDefaults) {
  EXPECT_EQ(RunConfigToYaml(ParseRunConfig("")), RunConfigToYaml(RunConfig{}));
}

void ExpectError(const std::string& yaml, const std::string& fragment) {
  try {
    ParseRunConfig(yaml, "test.yaml");
    FAIL() << "expected an error for: " << yaml;
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("test.yaml"), std::string::npos) << e.what();
  }
}

TEST(ConfigYaml, BadInputIsAClearError) {
  ExpectError("noise:\n  point_sigma_m: -0.02\n", "point_sigma_m");
  ExpectError("backend:\n  motion_mode: wobbly\n", "motion_mode");
  ExpectError("backend:\n  schedule: window:1\n", "schedule");
  ExpectError("noise:\n  point_sigma: 0.02\n", "unknown key 'noise.point_sigma'");
  ExpectError("solver:\n  x: 1\n", "unknown section 'solver'");
  ExpectError("noise:\n  point_sigma_m: abc\n", "wrong type");
  ExpectError("noise: [1, 2\n", "not valid YAML");
  ExpectError("backend:\n  linear_solver: qr\n", "unknown linear solver 'qr'");
  ExpectError("backend:\n  marginalisation: dense\n", "unknown marginalisation 'dense'");
  ExpectError("backend:\n  object_modes:\n    x: constant\n", "object_modes");
  // Sizes that would make OpenCV fail to allocate are errors naming the key, up front.
  ExpectError("frontend:\n  lk_window_px: 100000\n", "lk_window_px must be in 5..201");
  ExpectError("dataset:\n  lidar_fill_radius_px: 1000000\n", "lidar_fill_radius_px must be in 0..50");
  ExpectError("frontend:\n  odometry_gate_chi2: -1\n", "odometry_gate_chi2");
  ExpectError("frontend:\n  warped_search_radius_px: 500\n", "warped_search_radius_px must be in 0..200");
  ExpectError("frontend:\n  warped_search_min_ncc: 1.5\n", "warped_search_min_ncc");
}

TEST(ConfigYaml, MaskSourceAndLidarKeysRoundTripAndAreChecked) {
  const RunConfig c = ParseRunConfig(
      "frontend: {mask_ids_tracked: false}\n"
      "masks: {source: lidar_clusters, lidar_cluster_tolerance_m: 0.4, lidar_grow_px: 5, lidar_min_cluster_points: 30}\n");
  EXPECT_EQ(c.masks.source, MaskSourceKind::kLidarClusters);
  EXPECT_EQ(c.masks.lidar.segmentation.cluster_tolerance_m, 0.4);
  EXPECT_EQ(c.masks.lidar.grow_px, 5);
  EXPECT_EQ(c.masks.lidar.segmentation.min_cluster_points, 30);
  EXPECT_EQ(RunConfigToYaml(ParseRunConfig(RunConfigToYaml(c))), RunConfigToYaml(c));
  // Masks numbered per frame with ids taken as tracked would give a new object every frame.
  try {
    ParseRunConfig("masks: {source: lidar_clusters}\n", "cfg.yaml");
    FAIL() << "accepted lidar_clusters with mask_ids_tracked";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("mask_ids_tracked"), std::string::npos) << e.what();
  }
  EXPECT_THROW(ParseRunConfig("masks: {source: network}\n"), std::invalid_argument);
  EXPECT_THROW(ParseRunConfig("masks: {lidar_cluster_tolerance_m: -1}\n"), std::invalid_argument);
  EXPECT_THROW(ParseRunConfig("masks: {lidar_grow_px: 500}\n"), std::invalid_argument);
  EXPECT_THROW(ParseRunConfig("masks: {lidar_depth_background_spread: -0.1}\n"), std::invalid_argument);
  EXPECT_EQ(ParseRunConfig("masks: {lidar_depth_background_spread: 0.25}\n").masks.lidar_depth_background_spread, 0.25);
  // The mask source remakes LiDAR depth with the dataset's fill radius.
  EXPECT_EQ(MaskSourceOf(ParseRunConfig("dataset: {lidar_fill_radius_px: 5}\n")).depth_fill_radius_px, 5);
  // The shipped configuration for KITTI with a Velodyne and no masks uses it.
  const RunConfig traffic = LoadRunConfig(std::string(DSLAM_SOURCE_DIR) + "/config/kitti_raw_traffic.yaml");
  EXPECT_EQ(traffic.masks.source, MaskSourceKind::kLidarClusters);
  EXPECT_FALSE(traffic.frontend.association.mask_ids_tracked);
}

TEST(ConfigYaml, TheStereoSettingsAndTheShippedStereoConfiguration) {
  const RunConfig c = ParseRunConfig(
      "dataset: {stereo_lr_max_difference_px: 1.5, stereo_filter: wls, stereo_wls_lambda: 4000, "
      "stereo_wls_sigma_color: 2, stereo_wls_min_confidence: 100}\n");
  EXPECT_DOUBLE_EQ(c.dataset.stereo.lr_max_difference_px, 1.5);
  EXPECT_EQ(c.dataset.stereo.filter, "wls");
  EXPECT_DOUBLE_EQ(c.dataset.stereo.wls_lambda, 4000.0);
  EXPECT_DOUBLE_EQ(c.dataset.stereo.wls_sigma_color, 2.0);
  EXPECT_DOUBLE_EQ(c.dataset.stereo.wls_min_confidence, 100.0);
  EXPECT_EQ(RunConfigToYaml(ParseRunConfig(RunConfigToYaml(c))), RunConfigToYaml(c));
  EXPECT_THROW(ParseRunConfig("dataset: {stereo_filter: median}\n"), std::invalid_argument);
  EXPECT_THROW(ParseRunConfig("dataset: {stereo_lr_max_difference_px: -1}\n"), std::invalid_argument);
  // KITTI's stereo rig: depth from the pair, weighed as stereo depth (0.25 px / (721 px * 0.54 m)).
  const RunConfig stereo = LoadRunConfig(std::string(DSLAM_SOURCE_DIR) + "/config/kitti_stereo.yaml");
  EXPECT_EQ(stereo.dataset.depth_encoding, "stereo");
  EXPECT_NEAR(stereo.backend.noise.point_sigma_per_depth_sq, 0.25 / (721.0 * 0.54), 1e-5);
}

TEST(ConfigYaml, MissingFileIsAnError) {
  EXPECT_THROW(LoadRunConfig("/nonexistent/dslam.yaml"), std::invalid_argument);
}

TEST(ConfigYaml, AFileOfMegabytesIsRefusedWithoutReadingItAll) {
  try {
    LoadRunConfig("/dev/zero");  // endless: read only up to the bound
    FAIL() << "accepted /dev/zero";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("/dev/zero is over 4 MB"), std::string::npos) << e.what();
  }
  EXPECT_THROW(ParseRunConfig("dataset: {max_image_pixels: 0}\n"), std::invalid_argument);
  // .inf and .nan parse as numbers: refused for every setting, by name.
  for (const char* text : {"noise: {point_sigma_m: .inf}\n", "noise: {motion_sigma_m: .nan}\n",
                           "dataset: {stereo_wls_lambda: -.inf}\n"}) {
    try {
      ParseRunConfig(text, "cfg.yaml");
      FAIL() << "accepted " << text;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("is not a finite number"), std::string::npos) << e.what();
    }
  }
  EXPECT_EQ(ParseRunConfig("dataset: {max_image_pixels: 1000}\n").dataset.max_image_pixels, 1000);
}

}  // namespace
}  // namespace dslam
