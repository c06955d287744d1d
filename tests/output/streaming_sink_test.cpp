#include "output/streaming_sink.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <set>

#include "output/result_reader.h"
#include "output/trajectory_io.h"
#include "support/temp_paths.h"

namespace dslam {
namespace {
namespace fs = std::filesystem;

SE3 Pose(double x) { return SE3(Eigen::Quaterniond::Identity(), Vec3(x, 0.0, 0.0)); }

TEST(StreamingFileSink, WritesNothingUntilTheFirstEstimate) {
  const std::string dir = test::TempPath("stream_empty");
  {
    StreamingFileSink sink(dir);
    sink.flush();
  }
  EXPECT_FALSE(fs::exists(dir));
}

TEST(StreamingFileSink, AppendsFinalEstimatesReadableWhileTheRunGoes) {
  const std::string dir = test::TempPath("stream_rows");
  StreamingFileSink sink(dir);
  for (int k = 0; k < 3; ++k) sink.frameStamp(k, 1'000'000'000LL * (k + 1));
  sink.onlinePose(1'000'000'000, Pose(0.0));
  ObjectMotionEstimate m;
  m.object_id = 7, m.frame = 1, m.is_dynamic = true, m.speed_mps = 2.5;
  m.H_world = Pose(0.25);
  m.covariance = Mat6::Identity() * 0.04;
  m.speed_sigma_mps = 0.3;
  sink.motionFinal(m);
  sink.pointFinal({1, 42, -1, Vec3(1, 2, 3)});
  sink.pointFinal({1, 43, 7, Vec3(4, 5, 6)});
  sink.cameraFinal(0, Pose(0.0));
  sink.cameraFinal(1, Pose(1.5));
  // Flushed at each final camera: another reader sees the rows now, before the sink is gone.
  std::vector<int64_t> t_ns;
  const std::vector<SE3> cameras = ReadTumTrajectory(dir + "/camera_ours.tum", &t_ns);
  ASSERT_EQ(cameras.size(), 2u);
  EXPECT_EQ(t_ns[1], 2'000'000'000);
  EXPECT_DOUBLE_EQ(cameras[1].translation().x(), 1.5);
  EXPECT_EQ(ReadTumTrajectory(dir + "/camera_ours_online.tum").size(), 1u);
  const CsvTable speeds = ReadCsv(dir + "/object_speeds.csv");
  ASSERT_EQ(speeds.rows.size(), 1u);
  EXPECT_EQ(speeds.rows[0][speeds.column("object_id", "speeds")], "7");
  EXPECT_EQ(speeds.rows[0][speeds.column("est_speed_mps", "speeds")], "2.5");
  EXPECT_EQ(speeds.rows[0][speeds.column("gt_speed_mps", "speeds")], "");
  EXPECT_EQ(speeds.rows[0][speeds.column("speed_sigma_mps", "speeds")], "0.3");
  const CsvTable motions = ReadCsv(dir + "/object_motions.csv");  // every row has every column
  ASSERT_EQ(motions.rows.size(), 1u);
  EXPECT_EQ(motions.rows[0][motions.column("est_tx", "motions")], "0.25");
  EXPECT_EQ(motions.rows[0][motions.column("est_sigma_rz", "motions")], "0.2");
  // The object point at once; landmark 42 is still in sight at frame 1.
  const CsvTable points = ReadCsv(dir + "/map_points.csv");
  ASSERT_EQ(points.rows.size(), 1u);
  EXPECT_EQ(points.rows[0][0], "1");
  // A camera made final before its frame was announced is a bug of the caller, named.
  EXPECT_THROW(sink.cameraFinal(5, Pose(0.0)), std::logic_error);
}

// A landmark is written once, with its final value, when its last observation has left the window
// (a camera after it became final), and finish() writes those still in sight.
TEST(StreamingFileSink, WritesEachLandmarkOnceWhenItsSightingEnds) {
  const std::string dir = test::TempPath("stream_landmarks");
  StreamingFileSink sink(dir);
  for (int k = 0; k < 4; ++k) sink.frameStamp(k, 1'000'000'000LL * (k + 1));
  sink.pointFinal({0, 42, -1, Vec3(1, 0, 0)});
  sink.cameraFinal(0, Pose(0.0));
  sink.pointFinal({1, 42, -1, Vec3(1.5, 0, 0)});
  sink.pointFinal({1, 44, -1, Vec3(9, 0, 0)});
  sink.cameraFinal(1, Pose(1.0));
  sink.pointFinal({2, 45, -1, Vec3(7, 0, 0)});
  sink.cameraFinal(2, Pose(2.0));  // 42 and 44 were not seen in frame 2
  CsvTable points = ReadCsv(dir + "/map_points.csv");
  ASSERT_EQ(points.rows.size(), 2u);
  std::multiset<std::string> xs;
  for (const auto& row : points.rows) {
    EXPECT_EQ(row[0], "-1");
    xs.insert(row[2]);
  }
  EXPECT_EQ(xs, (std::multiset<std::string>{"1.5", "9"}));
  sink.finish();
  points = ReadCsv(dir + "/map_points.csv");
  ASSERT_EQ(points.rows.size(), 3u);
  EXPECT_EQ(points.rows[2][2], "7");
}

// With ground truth from the start (the simulator's), the object tables are the run's final ones:
// ground-truth columns filled in, and the pairs without estimate appended by finish().
TEST(StreamingFileSink, WithGroundTruthTheObjectTablesAreComplete) {
  GroundTruth gt;
  ObjectGroundTruth& car = gt.objects[3];
  car.object_id = 3;
  for (int k = 0; k < 4; ++k) {
    car.L_world_object[k] = Pose(0.5 * k);
    car.centroid_world[k] = Vec3(0.5 * k, 0, 0);
    car.observed_frames.insert(k);
  }
  const std::string dir = test::TempPath("stream_gt");
  StreamedFiles files;
  files.method = "slam_mot";
  files.object_suffix = "_slam_mot";
  files.online = files.map_points = false;
  files.kitti = true;
  StreamingFileSink sink(dir, files, &gt, 10.0);
  sink.frameStamp(0, 0);
  ObjectMotionEstimate m;
  m.object_id = 3, m.frame = 2, m.speed_mps = 4.0, m.H_world = Pose(0.4);
  sink.motionFinal(m);
  sink.cameraFinal(0, Pose(0.0));
  sink.finish();
  EXPECT_TRUE(fs::exists(dir + "/camera_slam_mot.kitti"));
  EXPECT_FALSE(fs::exists(dir + "/camera_slam_mot_online.tum"));
  EXPECT_FALSE(fs::exists(dir + "/map_points.csv"));
  const CsvTable speeds = ReadCsv(dir + "/object_speeds_slam_mot.csv");
  ASSERT_EQ(speeds.rows.size(), 3u);  // pairs 0->1, 1->2 (estimated), 2->3
  std::map<std::string, std::pair<std::string, std::string>> by_frame;
  for (const auto& row : speeds.rows) by_frame[row[0]] = {row[3], row[4]};
  EXPECT_EQ(by_frame.at("2"), std::make_pair(std::string("4"), std::string("5")));
  EXPECT_EQ(by_frame.at("1"), std::make_pair(std::string(""), std::string("5")));
  EXPECT_EQ(by_frame.at("3").first, "");
  const CsvTable motions = ReadCsv(dir + "/object_motions_slam_mot.csv");
  ASSERT_EQ(motions.rows.size(), 3u);
  for (const auto& row : motions.rows) EXPECT_EQ(row[motions.column("gt_tx", "motions")], "0.5");
}

}  // namespace
}  // namespace dslam
