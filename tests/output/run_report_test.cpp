#include "output/run_report.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "pipeline/run_sequence.h"
#include "simulation/scenarios.h"
#include "support/temp_paths.h"

namespace dslam {
namespace {

TEST(RunReport, MetricsJsonFollowsTheSchema) {
  MethodMetrics m;
  m.camera.rte_pct = 1.5;
  m.camera.ate_m = 0.2;
  const auto static_only = MethodMetricsJson(m, 1.0);
  for (const char* key : {"rte_pct", "rre_deg_per_m", "rse_pct", "omte_pct", "omre_deg_per_m", "omse_pct", "ate_m",
                          "me_t_m", "me_r_deg", "speed_err_mps", "object_coverage"})
    EXPECT_TRUE(static_only.contains(key)) << key;
  EXPECT_EQ(static_only["rte_pct"], 1.5);
  EXPECT_TRUE(static_only["omte_pct"].is_null());  // no object estimate: null, not 0
  EXPECT_TRUE(static_only["object_coverage"].is_null());
}

TEST(RunReport, WritesEveryResultFile) {
  ScenarioOptions opt;
  opt.num_frames = 15;
  const Sequence seq = MakeScenario("paper", opt);
  RunConfig config;
  config.backend.default_mode = MotionMode::kConstant;
  const MethodOutcomes outcomes = RunSequence(seq, config);
  const std::string dir = test::TempPath("report");
  WriteRunOutputs(dir, seq, outcomes, {{"command", "test"}});
  for (const char* f : {"metrics.json", "camera_gt.tum", "camera_ours.tum", "camera_static_only.tum",
                        "camera_slam_mot.tum", "camera_ours.kitti", "object_motions.csv", "object_speeds.csv",
                        "object_motions_slam_mot.csv", "objects.csv", "map_points.csv", "object_centroids_gt.csv"})
    EXPECT_TRUE(std::filesystem::exists(dir + "/" + f)) << f;
  const auto metrics = nlohmann::json::parse(std::ifstream(dir + "/metrics.json"));
  for (const char* method : {"ours", "slam_mot", "static_only"}) EXPECT_TRUE(metrics["methods"].contains(method));
  EXPECT_EQ(metrics["run"]["command"], "test");
  EXPECT_TRUE(metrics["methods"]["static_only"]["omte_pct"].is_null());
  EXPECT_TRUE(metrics["methods"]["ours"]["omte_pct"].is_number());

  std::ifstream speeds(dir + "/object_speeds.csv");
  std::string header, line;
  std::getline(speeds, header);
  EXPECT_EQ(header,
            "frame,object_id,is_dynamic,est_speed_mps,gt_speed_mps,speed_sigma_mps,centroid_x_m,centroid_y_m,"
            "centroid_z_m,box_x,box_y,box_w,box_h");
  int rows = 0, with_centroid = 0;
  while (std::getline(speeds, line)) {
    ++rows;
    // Every row has the header's 13 fields; an estimated one says where its object was (the simulator gives
    // no image, so no box).
    EXPECT_EQ(std::count(line.begin(), line.end(), ','), 12) << line;
    if (line.find(",,,,") == line.size() - 4 && line.find(",,,,,,,") == std::string::npos) ++with_centroid;
  }
  EXPECT_EQ(rows, 14);  // one object, 14 frame pairs
  EXPECT_GT(with_centroid, 0);
  const std::string table = FormatMetricsTable(outcomes, "title");
  EXPECT_NE(table.find("Object OMTE (%)"), std::string::npos);
  EXPECT_NE(table.find("SLAM+MOT"), std::string::npos);
  std::filesystem::remove_all(dir);
}

TEST(RunReport, UnwritableDirectoryIsAnError) {
  EXPECT_THROW(WriteRunOutputs("/proc/dslam_cannot_write", Sequence{}, {}, {}), std::runtime_error);
}

}  // namespace
}  // namespace dslam
