#include "data/odometry_file.h"

#include <gtest/gtest.h>

#include <fstream>

#include "support/temp_paths.h"

namespace dslam {
namespace {

TEST(OdometryFile, RoundTripsIncrementsAndSigmas) {
  std::map<int, OdometryMeasurement> odometry;
  odometry[1].T_prev_curr = SE3::Exp((Vec6() << 0.1, -0.02, 1.2, 0.01, -0.03, 0.002).finished());
  odometry[1].sigma << 0.05, 0.05, 0.06, 0.001, 0.002, 0.003;
  odometry[3].T_prev_curr = SE3::Exp((Vec6() << 0.0, 0.0, 0.9, 0.0, 0.01, 0.0).finished());
  const std::string path = test::TempPath("odometry.txt");
  WriteOdometryFile(path, odometry);
  const auto read = ReadOdometryFile(path);
  ASSERT_EQ(read.size(), 2u);
  for (const auto& [k, m] : odometry) {
    EXPECT_LT((read.at(k).T_prev_curr.inverse() * m.T_prev_curr).Log().norm(), 1e-12);
    EXPECT_TRUE(read.at(k).sigma.isApprox(m.sigma, 1e-12));
  }
}

std::string ErrorOf(const std::string& line) {
  const std::string path = test::TempPath("bad_odometry.txt");
  std::ofstream(path) << "# comment\n" << line << "\n";
  try {
    ReadOdometryFile(path);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

TEST(OdometryFile, NamesTheFileLineAndProblem) {
  const std::string good = "1 0 0 1 0 0 0 1 0.1 0.1 0.1 0.01 0.01 0.01";
  EXPECT_EQ(ErrorOf(good), "");
  EXPECT_NE(ErrorOf("1 0 0 nan 0 0 0 1 0.1 0.1 0.1 0.01 0.01 0.01").find(":2: tz 'nan' is not a finite number"),
            std::string::npos);
  EXPECT_NE(ErrorOf("1 0 0 1 0 0 0 1 0.1").find(":2: expected 14 fields"), std::string::npos);
  EXPECT_NE(ErrorOf("1 0 0 1 0 0 0 2 0.1 0.1 0.1 0.01 0.01 0.01").find("unit norm"), std::string::npos);
  EXPECT_NE(ErrorOf("1 0 0 1 0 0 0 1 0.1 0.1 0 0.01 0.01 0.01").find("sigma_tz must be positive"), std::string::npos);
  EXPECT_NE(ErrorOf(good + "\n" + good).find(":3: frame 1 does not come after frame 1"), std::string::npos);
  EXPECT_NE(ErrorOf("0 0 0 1 0 0 0 1 0.1 0.1 0.1 0.01 0.01 0.01").find("frame must be >= 1"), std::string::npos);
}

}  // namespace
}  // namespace dslam
