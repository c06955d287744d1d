// `dslam run`'s one stream (front-end and methods in parallel, the baselines in lockstep beside ours,
// files and metrics as the estimates become final) computes what the front-end alone followed by the
// collected methods computes.
#include "pipeline/image_run.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "app/run_command.h"
#include "output/trajectory_io.h"
#include "pipeline/run_defaults.h"
#include "pipeline/run_sequence.h"
#include "support/rendered_city.h"
#include "support/same_run.h"
#include "support/temp_paths.h"

namespace dslam {
namespace {

TEST(ImageRun, TheStreamedRunEqualsTheFrontEndFollowedByTheCollectedMethods) {
  const std::string dir = test::RenderedCity("staged_city", 12);
  const RunConfig config = DefaultRunConfig(EntryPoint::kRun);
  const ImageDataset data(dir, config.dataset);

  ImageRunSummary frontend_summary;
  std::ostringstream collected_log;
  const Sequence seq = RunImageFrontend(data, config, 0, nullptr, &frontend_summary, &collected_log);
  ASSERT_TRUE(frontend_summary.has_ground_truth);
  const MethodOutcomes collected = RunSequence(seq, config);
  const std::string collected_dir = test::TempPath("image_run_collected");
  WriteRunOutputs(collected_dir, seq, collected, {});

  ImageRunOptions run;
  run.out_dir = test::TempPath("image_run_streamed");
  std::ostringstream streamed_log;
  run.frame_log = &streamed_log;
  run.keep_frames = {3, 8};
  const ImageRunResult streamed = RunImageStreamed(data, config, run);

  EXPECT_EQ(streamed.summary.frames, 12);
  EXPECT_TRUE(streamed.summary.has_ground_truth);
  EXPECT_EQ(streamed.summary.mean_static_tracks, frontend_summary.mean_static_tracks);
  EXPECT_FALSE(streamed.summary.latency.empty());
  EXPECT_EQ(streamed_log.str(), collected_log.str());  // the front-end's own log, row for row
  ASSERT_EQ(streamed.outcomes.size(), 3u);
  for (const auto& [method, outcome] : collected) {
    test::ExpectSameMetrics(streamed.outcomes.at(method).metrics, outcome.metrics, ToString(method));
    EXPECT_GT(streamed.outcomes.at(method).result.wall_time_s, 0.0) << ToString(method);
  }

  for (const char* name : {"camera_ours.tum", "camera_ours_online.tum", "camera_static_only.tum", "camera_slam_mot.tum",
                           "camera_gt.tum"})
    test::ExpectSameTrajectory(run.out_dir + "/" + name, collected_dir + "/" + name);
  for (const char* name : {"object_speeds.csv", "object_motions.csv", "object_speeds_slam_mot.csv", "map_points.csv",
                           "objects.csv", "object_centroids_gt.csv"})
    test::ExpectSameRows(run.out_dir + "/" + name, collected_dir + "/" + name);

  // Ours' final motions of the frames asked for, and only those.
  std::vector<ObjectMotionEstimate> want;
  for (const ObjectMotionEstimate& m : collected.at(Method::kOurs).result.estimate.object_motions)
    if (m.frame == 3 || m.frame == 8) want.push_back(m);
  ASSERT_FALSE(want.empty());
  ASSERT_EQ(streamed.kept_motions.size(), want.size());
  for (const ObjectMotionEstimate& m : streamed.kept_motions) EXPECT_TRUE(m.frame == 3 || m.frame == 8);
  // And those frames' image and masks as the front-end saw them (the overlays are drawn from them).
  ASSERT_EQ(streamed.kept_frames.size(), 2u);
  for (int k : {3, 8}) {
    ASSERT_TRUE(streamed.kept_frames.count(k)) << k;
    const KeptFrame& kept = streamed.kept_frames.at(k);
    const ImageFrame read = data.read(k);
    ASSERT_FALSE(read.instance_ids.empty());
    EXPECT_EQ(cv::norm(kept.image, read.image, cv::NORM_INF), 0.0) << k;
    EXPECT_EQ(cv::norm(kept.instance_ids, read.instance_ids, cv::NORM_INF), 0.0) << k;
  }
}

// A baseline alone runs without ours (nothing of ours is written), and gets what it gets beside ours.
TEST(ImageRun, ABaselineAloneRunsWithoutOurs) {
  const std::string dir = test::RenderedCity("staged_city", 12);
  const RunConfig config = DefaultRunConfig(EntryPoint::kRun);
  const ImageDataset data(dir, config.dataset);
  const Sequence seq = RunImageFrontend(data, config, 0, nullptr, nullptr);
  RunSequenceOptions collected_run;
  collected_run.methods = {Method::kStaticOnly};
  const MethodOutcomes collected = RunSequence(seq, config, collected_run);

  ImageRunOptions run;
  run.methods = {Method::kStaticOnly};
  run.out_dir = test::TempPath("image_run_static_only");
  const ImageRunResult streamed = RunImageStreamed(data, config, run);
  ASSERT_EQ(streamed.outcomes.size(), 1u);
  test::ExpectSameMetrics(streamed.outcomes.at(Method::kStaticOnly).metrics,
                          collected.at(Method::kStaticOnly).metrics, "static_only");
  EXPECT_GT(streamed.outcomes.at(Method::kStaticOnly).result.wall_time_s, 0.0);
  EXPECT_TRUE(std::filesystem::exists(run.out_dir + "/camera_static_only.tum"));
  EXPECT_FALSE(std::filesystem::exists(run.out_dir + "/camera_ours.tum"));
  EXPECT_TRUE(streamed.ours_objects.empty());
}

// A long run from a short recording (the memory benchmark's): the dataset forwards and backwards, each
// method's files as long as the drive, nothing evaluated; back at the first recorded frame, ours' camera is
// back where it started.
TEST(ImageRun, ReplaysTheDatasetForwardsAndBackwardsAsOneDrive) {
  const std::string dir = test::RenderedCity("staged_city", 12);
  const RunConfig config = DefaultRunConfig(EntryPoint::kRun);
  const ImageDataset data(dir, config.dataset);
  ImageRunOptions run;
  run.out_dir = test::TempPath("image_run_ping_pong");
  run.max_frames = 23;  // 0..11, 10..0: step 22 is recorded frame 0 again
  run.ping_pong = true;
  int frames_read = 0;
  run.after_frame = [&](int done) { EXPECT_EQ(done, ++frames_read); };
  const ImageRunResult result = RunImageStreamed(data, config, run);
  EXPECT_EQ(frames_read, 23);
  EXPECT_EQ(result.summary.frames, 23);
  EXPECT_FALSE(result.summary.has_ground_truth);
  EXPECT_FALSE(result.outcomes.at(Method::kOurs).metrics.camera.rte_pct.has_value());  // nothing evaluated
  for (const char* name : {"camera_ours.tum", "camera_static_only.tum", "camera_slam_mot.tum"}) {
    std::vector<int64_t> t_ns;
    const std::vector<SE3> poses = ReadTumTrajectory(run.out_dir + "/" + name, &t_ns);
    ASSERT_EQ(poses.size(), 23u) << name;
    EXPECT_NEAR(static_cast<double>(t_ns[22] - t_ns[0]), 22e9 / data.frameRateHz(), 1e3) << name;  // 22 periods
  }
  const std::vector<SE3> ours = ReadTumTrajectory(run.out_dir + "/camera_ours.tum");
  const double returned_m = (ours[22].translation() - ours[0].translation()).norm();
  const double farthest_m = (ours[11].translation() - ours[0].translation()).norm();
  EXPECT_GT(farthest_m, 1.0);
  EXPECT_LT(returned_m, 0.05 * farthest_m) << "back at the first frame, " << returned_m << " m from where it started";
  ImageRunOptions without_frames = run;
  without_frames.max_frames = 0;
  EXPECT_THROW(RunImageStreamed(data, config, without_frames), std::invalid_argument);
}

}  // namespace
}  // namespace dslam
