#include "output/streaming_sink.h"

#include <gtest/gtest.h>

#include <filesystem>

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
  const CsvTable points = ReadCsv(dir + "/map_points.csv");
  ASSERT_EQ(points.rows.size(), 2u);
  EXPECT_EQ(points.rows[0][0], "-1");  // a landmark: no frame
  EXPECT_EQ(points.rows[1][0], "1");
  // A camera made final before its frame was announced is a bug of the caller, named.
  EXPECT_THROW(sink.cameraFinal(5, Pose(0.0)), std::logic_error);
}

}  // namespace
}  // namespace dslam
