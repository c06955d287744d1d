// KITTI tracking ground-truth replay: what `dslam kitti-replay` must show on sequences 0000, 0003
// and 0005 of the shared data (skipped when ../shared/data is absent).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "app/kitti_replay_command.h"
#include "data/kitti_dataset.h"
#include "pipeline/run_sequence.h"
#include "simulation/kitti_replay.h"
#include "support/shared_data.h"
#include "support/temp_paths.h"

namespace dslam {
namespace {

namespace fs = std::filesystem;

#define REQUIRE_SHARED_DATA() \
  if (!fs::exists(test::KittiTrackingDir() + "/label_02/0000.txt")) GTEST_SKIP() << "shared data absent: " << test::KittiTrackingDir()

MethodOutcomes Replay(const std::string& seq, double sigma, const std::vector<Method>& methods, uint64_t seed = 1) {
  KittiReplayOptions replay;
  replay.noise.point_sigma_m = sigma;
  replay.seed = seed;
  const Sequence sequence = MakeKittiReplay(LoadKittiGroundTruth(test::KittiTrackingDir(), seq), replay);
  RunConfig config;
  config.backend.default_mode = DefaultsOf(EntryPoint::kKittiReplay).mode;
  config.backend.noise.point_sigma_m = sigma;
  RunSequenceOptions run;
  run.methods = methods;
  run.object_category = "VEHICLE";
  return RunSequence(sequence, config, run);
}

class KittiReplaySequence : public ::testing::TestWithParam<std::string> {};

TEST_P(KittiReplaySequence, MeetsThePaperLevelTargetsOnVehicles) {
  REQUIRE_SHARED_DATA();
  const auto outcomes = Replay(GetParam(), 0.02, {Method::kOurs, Method::kStaticOnly, Method::kSlamMot});
  std::cout << FormatMetricsTable(outcomes, "KITTI " + GetParam() + ", sigma 0.02, vehicles within 22 m");
  const auto& ours = outcomes.at(Method::kOurs).metrics;
  const auto& static_only = outcomes.at(Method::kStaticOnly).metrics;
  const auto& slam_mot = outcomes.at(Method::kSlamMot).metrics;
  ASSERT_TRUE(ours.objects && ours.objects->omse_pct && ours.objects->omte_pct);
  EXPECT_LT(*ours.objects->omse_pct, 5.0);
  EXPECT_LT(*ours.objects->omte_pct, 10.0);
  EXPECT_GE(*ours.objects->object_coverage, 0.9);
  EXPECT_LE(*ours.camera.rte_pct, *static_only.camera.rte_pct);
  EXPECT_LT(*ours.objects->omte_pct, *slam_mot.objects->omte_pct);
}

INSTANTIATE_TEST_SUITE_P(SharedSequences, KittiReplaySequence, ::testing::Values("0000", "0003", "0005"));

TEST(KittiReplay, ObjectMotionErrorGrowsWithPointNoise) {
  REQUIRE_SHARED_DATA();
  std::vector<double> omte;
  for (double sigma : {0.02, 0.04, 0.06})
    omte.push_back(*Replay("0000", sigma, {Method::kOurs}).at(Method::kOurs).metrics.objects->omte_pct);
  std::cout << "KITTI 0000 OMTE at sigma 0.02 / 0.04 / 0.06: " << omte[0] << " / " << omte[1] << " / " << omte[2]
            << " %\n";
  EXPECT_LT(omte[0], omte[1]);
  EXPECT_LT(omte[1], omte[2]);
}

TEST(KittiReplay, ParkedCarsWhoseLabelsJitterDoNotPullTheCamera) {
  REQUIRE_SHARED_DATA();
  // 0000's parked cars are static within the noise, but their labels move them by centimetres a frame;
  // merged into the map as independent points they pulled ours' camera 3 to 11 % past static-only's
  // (ATE) at these noise levels. Weighed as one landmark of their jitter, they no longer do.
  for (const double sigma : {0.04, 0.06}) {
    for (uint64_t seed = 1; seed <= 2; ++seed) {
      const auto outcomes = Replay("0000", sigma, {Method::kOurs, Method::kStaticOnly}, seed);
      const double ours = outcomes.at(Method::kOurs).metrics.camera.ate_m;
      const double static_only = outcomes.at(Method::kStaticOnly).metrics.camera.ate_m;
      std::cout << "KITTI 0000, sigma " << sigma << ", seed " << seed << ": camera ATE ours / static-only = " << ours
                << " / " << static_only << " m\n";
      EXPECT_LE(ours, 1.02 * static_only) << "sigma " << sigma << ", seed " << seed;
    }
  }
}

TEST(KittiReplay, CommandWritesTheObjectTable) {
  REQUIRE_SHARED_DATA();
  KittiReplayCommandOptions o;
  o.data_dir = test::KittiTrackingDir();
  o.sequence = "0003";
  o.quiet = true;
  o.schedule = "window:10";
  o.out_dir = test::TempPath("kitti_cmd");
  std::ostringstream out, err;
  ASSERT_EQ(RunKittiReplayCommand(o, out, err), 0) << err.str();
  EXPECT_NE(out.str().find("Per object (ours)"), std::string::npos);
  for (const char* f : {"metrics.json", "objects.csv", "object_speeds.csv", "camera_gt.tum"})
    EXPECT_TRUE(fs::exists(o.out_dir + "/" + f)) << f;
  std::ifstream objects(o.out_dir + "/objects.csv");
  std::string header;
  std::getline(objects, header);
  EXPECT_EQ(header,
            "object_id,category,gt_frame_pairs,frames_estimated,omte_pct,omre_deg_per_m,omse_pct,mean_gt_speed_kmh,"
            "mean_est_speed_kmh");
  fs::remove_all(o.out_dir);
}

TEST(KittiReplay, BadInputIsAClearErrorNotACrash) {
  const fs::path dir = fs::path(test::TempPath("kitti_bad"));
  fs::create_directories(dir / "label_02");
  std::ofstream(dir / "pose_gt.txt") << "0 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1\n1 1 0 0 0 0 1 0 0 0 0 1 1 0 0 0 1\n";
  std::ofstream(dir / "label_02" / "0007.txt") << "0 0 Car 0 0 -1.5 10 10 50 50 1.5 1.6\n";
  KittiReplayCommandOptions o;
  o.data_dir = dir.string();
  o.sequence = "0007";
  o.out_dir = (dir / "out").string();
  std::ostringstream out, err;
  EXPECT_EQ(RunKittiReplayCommand(o, out, err), 2);
  EXPECT_NE(err.str().find("0007.txt:1: expected 17-18 fields"), std::string::npos) << err.str();
  o.sequence = "0008";
  err.str("");
  EXPECT_EQ(RunKittiReplayCommand(o, out, err), 2);
  EXPECT_NE(err.str().find("no object ground truth for sequence 0008"), std::string::npos) << err.str();
  fs::remove_all(dir);
}

}  // namespace
}  // namespace dslam
