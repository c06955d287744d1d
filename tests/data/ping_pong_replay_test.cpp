#include "data/ping_pong_replay.h"

#include <gtest/gtest.h>

#include <vector>

namespace dslam {
namespace {

TEST(PingPongReplay, GoesForwardsThenBackwardsWithoutRepeatingTheEnds) {
  std::vector<int> frames;
  for (int i = 0; i < 9; ++i) frames.push_back(PingPongFrame(i, 4));
  EXPECT_EQ(frames, (std::vector<int>{0, 1, 2, 3, 2, 1, 0, 1, 2}));
  EXPECT_EQ(PingPongFrame(5, 2), 1);  // 0 1 0 1 0 1
  EXPECT_THROW(PingPongFrame(0, 1), std::invalid_argument);
  EXPECT_THROW(PingPongFrame(-1, 4), std::invalid_argument);
}

// The odometry of the drive, composed step by step, is where the recorded frame is: the steps backwards
// undo the recorded increments.
TEST(PingPongReplay, ItsOdometryFollowsTheRecordedFrameItIsAt) {
  const int n = 4;
  std::vector<SE3> T_world_recorded;  // a camera turning and driving
  for (int k = 0; k < n; ++k) T_world_recorded.push_back(SE3::Exp((Vec6() << 0.5 * k, 0.1, k, 0.0, 0.05 * k, 0.0).finished()));
  const auto odometry_into = [&](int k) -> std::optional<OdometryMeasurement> {
    if (k == 0) return std::nullopt;
    OdometryMeasurement m;
    m.T_prev_curr = T_world_recorded[k - 1].inverse() * T_world_recorded[k];
    return m;
  };
  SE3 T_world_drive = T_world_recorded[0];
  for (int i = 0; i < 15; ++i) {
    ImageFrame f;
    f.flow_to_next = cv::Mat(2, 2, CV_32FC2, cv::Scalar(0.0f, 0.0f));
    ToPingPongStep(i, n, 100'000'000, odometry_into, &f);
    EXPECT_EQ(f.frame_index, i);
    EXPECT_EQ(f.t_ns, i * 100'000'000LL);
    EXPECT_EQ(f.odometry.has_value(), i > 0);
    if (f.odometry) T_world_drive = T_world_drive * f.odometry->T_prev_curr;
    const int k = PingPongFrame(i, n);
    EXPECT_LT((T_world_drive.matrix() - T_world_recorded[k].matrix()).norm(), 1e-9) << "step " << i;
    // Flow to the next frame only where the next step is the next recorded frame.
    EXPECT_EQ(f.flow_to_next.empty(), PingPongFrame(i + 1, n) != k + 1) << "step " << i;
  }
}

}  // namespace
}  // namespace dslam
