#include "output/trajectory_io.h"

#include <gtest/gtest.h>

#include "support/temp_paths.h"

#include <filesystem>
#include <fstream>

namespace dslam {
namespace {

using test::TempDir;
using test::TempPath;


TEST(TrajectoryIo, TumRoundTrip) {
  const std::vector<SE3> poses = {SE3::Identity(), SE3::Exp((Vec6() << 1, 2, 3, 0.1, -0.2, 0.3).finished())};
  const std::vector<int64_t> t_ns = {0, 100'000'000};
  const std::string path = TempPath("traj.tum");
  WriteTumTrajectory(path, t_ns, poses);
  std::vector<int64_t> t_back;
  const auto back = ReadTumTrajectory(path, &t_back);
  ASSERT_EQ(back.size(), 2u);
  EXPECT_EQ(t_back, t_ns);
  EXPECT_TRUE(back[1].isApprox(poses[1], 1e-8));
  std::filesystem::remove(path);
}

TEST(TrajectoryIo, KittiFormatHasTwelveNumbersPerLine) {
  const std::string path = TempPath("traj.kitti");
  WriteKittiTrajectory(path, {SE3(Eigen::Quaterniond::Identity(), Vec3(1, 2, 3))});
  std::ifstream in(path);
  std::vector<double> v;
  double x;
  while (in >> x) v.push_back(x);
  ASSERT_EQ(v.size(), 12u);
  EXPECT_EQ(v[0], 1.0);
  EXPECT_EQ(v[3], 1.0);
  EXPECT_EQ(v[7], 2.0);
  EXPECT_EQ(v[11], 3.0);
  std::filesystem::remove(path);
}

TEST(TrajectoryIo, MalformedLineNamesFileAndLine) {
  const std::string path = TempPath("bad.tum");
  std::ofstream(path) << "# comment\n0 0 0 0 0 0 0 1\n0.1 0 0 zero 0 0 0 1\n";
  try {
    ReadTumTrajectory(path);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path + ":3"), std::string::npos) << e.what();
  }
  std::filesystem::remove(path);
  EXPECT_THROW(ReadTumTrajectory(path), std::runtime_error);
  EXPECT_THROW(WriteKittiTrajectory("/nonexistent/dir/x.kitti", {}), std::runtime_error);
}

}  // namespace
}  // namespace dslam
