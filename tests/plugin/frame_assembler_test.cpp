#include "plugin/frame_assembler.h"

#include <gtest/gtest.h>

namespace dslam {
namespace {

const cv::Mat kImage(4, 6, CV_8UC3, cv::Scalar(1, 2, 3));
const cv::Mat kDepth(4, 6, CV_32FC1, cv::Scalar(2.0f));
const cv::Mat kMask(4, 6, CV_16UC1, cv::Scalar(0));

StampedPose PoseAt(double z) {
  StampedPose p;
  p.T_odom_camera = SE3(Eigen::Quaterniond::Identity(), Vec3(0, 0, z));
  return p;
}

TEST(FrameAssembler, BoundsThePendingPixelsInBytesAsWellAsInSets) {
  // --max-pending 1000 with 1 MB images grew to gigabytes: the bytes waiting are bounded too.
  AssemblerParams params;
  params.max_pending = 64;
  params.max_pending_bytes = size_t{1} << 20;  // 1 MiB
  FrameAssembler a(params, [] { return int64_t{0}; });
  const cv::Mat big(300, 400, CV_8UC3, cv::Scalar(1));  // 360 kB: two fit, not three
  for (int k = 0; k < 5; ++k) a.addColour(k * 100'000'000, big);
  EXPECT_EQ(a.counters().dropped_queue_full, 3u);
  params.max_pending = 65;
  EXPECT_THROW(params.validate(), std::invalid_argument);
}

TEST(FrameAssembler, IncrementNoiseIsTheTwistSigmaTimesTheTimeBetweenFramesElseTheDefault) {
  AssemblerParams params;
  params.expect_odometry = true;
  params.default_increment_sigma = Vec6::Constant(0.02);
  FrameAssembler a(params, [] { return int64_t{0}; });
  const cv::Mat colour(4, 6, CV_8UC3, cv::Scalar(1)), depth(4, 6, CV_32FC1, cv::Scalar(2.0f));
  auto add = [&](int64_t t, const StampedPose& pose) {
    a.addOdometry(t, pose);
    a.addMask(t, kMask);
    a.addColour(t, colour);
    a.addDepth(t, depth);
  };
  StampedPose with_twist = PoseAt(1.0);
  with_twist.twist_sigma_per_s = (Vec6() << 0.5, 0.5, 1.0, 0.1, 0.1, 0.2).finished();
  add(0, PoseAt(0.0));
  add(200'000'000, with_twist);  // 0.2 s later
  add(300'000'000, PoseAt(2.0));
  const auto frames = a.takeReady();
  ASSERT_EQ(frames.size(), 3u);
  EXPECT_FALSE(frames[0].odometry);
  ASSERT_TRUE(frames[1].odometry);
  EXPECT_TRUE(frames[1].odometry->sigma.isApprox(0.2 * *with_twist.twist_sigma_per_s, 1e-12));
  ASSERT_TRUE(frames[2].odometry);
  EXPECT_TRUE(frames[2].odometry->sigma.isApprox(Vec6::Constant(0.02)));
  // A non-positive twist sigma is a rejected part.
  StampedPose bad = PoseAt(3.0);
  bad.twist_sigma_per_s = Vec6::Zero();
  a.addOdometry(400'000'000, bad);
  EXPECT_EQ(a.counters().rejected_invalid, 1u);
}

void AddAll(FrameAssembler& a, int64_t t, double z) {
  a.addOdometry(t, PoseAt(z));
  a.addMask(t, kMask);
  a.addDepth(t, kDepth);
  a.addColour(t, kImage);
}

// A wall clock the test moves by hand, so that no timeout depends on the machine's speed.
struct FakeClock {
  int64_t now_ns = 0;
  WallClockNs fn() {
    return [this] { return now_ns; };
  }
};

AssemblerParams WithOdometry() {
  AssemblerParams p;
  p.expect_odometry = true;
  return p;
}

TEST(FrameAssembler, ReleasesCompleteSetsInStampOrderWithOdometryIncrements) {
  FrameAssembler a(WithOdometry());
  // Frame 200 completes before frame 100's colour arrives: it waits behind it.
  AddAll(a, 200, 3.0);
  a.addOdometry(100, PoseAt(1.0));
  a.addDepth(100, kDepth);
  a.addMask(100, kMask);
  EXPECT_TRUE(a.takeReady().empty());
  a.addColour(100, kImage);
  const auto frames = a.takeReady();
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_EQ(frames[0].t_ns, 100);
  EXPECT_EQ(frames[0].frame_index, 0);
  EXPECT_FALSE(frames[0].odometry);  // the first frame has no increment
  EXPECT_EQ(frames[1].frame_index, 1);
  ASSERT_TRUE(frames[1].odometry);
  EXPECT_NEAR(frames[1].odometry->T_prev_curr.translation().z(), 2.0, 1e-12);
  EXPECT_EQ(a.counters().frames_assembled, 2u);
  EXPECT_EQ(a.counters().parts_received, 8u);
}

TEST(FrameAssembler, AFramesTimingStartsAtItsFirstPartAndSumsItsDecoding) {
  FakeClock clock;
  FrameAssembler a(WithOdometry(), clock.fn());
  clock.now_ns = 5'000;
  a.addDepth(100, kDepth, {3'000, 1.5});  // arrived at 3 us (taken from the reader), decoded in 1.5 ms
  clock.now_ns = 6'000;
  a.addMask(100, kMask, {0, 0.25});       // no arrival time given: when the assembler got it
  clock.now_ns = 7'000;
  a.addOdometry(100, PoseAt(0.0), {2'500, 0.0});
  a.addColour(100, kImage, {4'000, 2.0});
  clock.now_ns = 9'000;
  const auto frames = a.takeReady();
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].timing.received_ns, 2'500);
  EXPECT_DOUBLE_EQ(frames[0].timing.decode_ms, 3.75);
  EXPECT_EQ(frames[0].timing.assembled_ns, 9'000);
  EXPECT_EQ(frames[0].timing.frontend_start_ns, 0);  // the pipeline's to fill in
}

TEST(FrameAssembler, WithMasksFromTheLidarAFrameNeedsAScanInsteadOfAMask) {
  AssemblerParams p;
  p.expect_mask = false;
  p.expect_lidar = true;
  FrameAssembler a(p);
  a.addColour(100, kImage);
  a.addDepth(100, kDepth);
  EXPECT_TRUE(a.takeReady().empty());  // waits for its scan
  LidarPart scan;
  scan.points_camera = {{0.0f, 0.0f, 5.0f}, {1.0f, 0.5f, 7.0f}};
  scan.origin_camera = {0.0f, -0.08f, -0.27f};
  scan.up_camera = {0.0f, -1.0f, 0.0f};
  a.addLidar(100, scan);
  const auto frames = a.takeReady();
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].lidar_points_camera, scan.points_camera);
  EXPECT_EQ(frames[0].lidar_origin_camera, scan.origin_camera);
  EXPECT_TRUE(frames[0].instance_ids.empty());
  EXPECT_EQ(a.counters().parts_received, 3u);
}

TEST(FrameAssembler, DropsIncompleteSetsAfterTheTimeoutAndCountsThem) {
  AssemblerParams p = WithOdometry();
  p.timeout_ns = 1000;
  FakeClock clock;
  FrameAssembler a(p, clock.fn());
  a.addColour(100, kImage);  // never completed
  AddAll(a, 600, 1.0);
  EXPECT_TRUE(a.takeReady().empty());  // 500 ns behind the newest: still waiting
  AddAll(a, 1200, 2.0);
  const auto frames = a.takeReady();  // 1100 ns behind: dropped; 600 and 1200 go
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_EQ(frames[0].t_ns, 600);
  EXPECT_EQ(a.counters().dropped_incomplete, 1u);
}

// Frames of which no part arrived (lost whole on the way: DDS does not always say so) are counted from the
// stamps, by the nominal period; a frame dropped incomplete is counted as that, not as missing.
TEST(FrameAssembler, CountsTheFramesOfWhichNoPartArrivedByTheNominalPeriod) {
  AssemblerParams p = WithOdometry();
  p.nominal_period_ns = 100;
  p.timeout_ns = 250;
  FakeClock clock;
  FrameAssembler a(p, clock.fn());
  AddAll(a, 1000, 0.0);
  AddAll(a, 1100, 1.0);
  AddAll(a, 1400, 4.0);  // 1200 and 1300 never came
  a.addColour(1500, kImage);  // incomplete
  AddAll(a, 1590, 6.0);       // 1600 a little early (stamps jitter)
  AddAll(a, 1900, 9.0);       // 1700, 1800 missing; 1500 times out behind it
  EXPECT_EQ(a.takeReady().size(), 5u);
  EXPECT_EQ(a.counters().dropped_incomplete, 1u);
  EXPECT_EQ(a.counters().frames_missing, 4u);
  // Without a nominal period nothing is counted as missing.
  p.nominal_period_ns = 0;
  FrameAssembler b(p, clock.fn());
  AddAll(b, 1000, 0.0);
  AddAll(b, 1400, 4.0);
  EXPECT_EQ(b.takeReady().size(), 2u);
  EXPECT_EQ(b.counters().frames_missing, 0u);
  p.nominal_period_ns = -1;
  EXPECT_THROW(p.validate(), std::invalid_argument);
}

TEST(FrameAssembler, DropsTheLastIncompleteSetOnceTheStreamFallsSilent) {
  // No newer stamp follows the last frame of a stream: only wall time can time it out.
  AssemblerParams p = WithOdometry();
  p.silence_timeout_ns = 2'000;
  FakeClock clock;
  FrameAssembler a(p, clock.fn());
  AddAll(a, 100, 0.0);
  a.addColour(200, kImage);  // its depth, mask and odometry never come
  clock.now_ns = 1'000;
  a.addDepth(200, kDepth);  // a part arriving restarts the silence
  EXPECT_EQ(a.takeReady().size(), 1u);
  clock.now_ns = 2'999;
  EXPECT_TRUE(a.takeReady().empty());
  EXPECT_EQ(a.counters().dropped_incomplete, 0u);
  clock.now_ns = 3'000;
  EXPECT_TRUE(a.takeReady().empty());
  EXPECT_EQ(a.counters().dropped_incomplete, 1u);
  // The stream resumes: the next complete set is released at once.
  AddAll(a, 300, 1.0);
  const auto frames = a.takeReady();
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_EQ(frames[0].t_ns, 300);
  ASSERT_TRUE(frames[0].odometry);
  EXPECT_NEAR(frames[0].odometry->T_prev_curr.translation().z(), 1.0, 1e-12);
}

TEST(FrameAssembler, BoundsThePendingSetsByDroppingTheOldest) {
  AssemblerParams p;
  p.max_pending = 3;
  FrameAssembler a(p);
  for (int64_t t = 1; t <= 5; ++t) a.addColour(t, kImage);  // five incomplete stamps, room for three
  EXPECT_EQ(a.counters().dropped_queue_full, 2u);
  a.addColour(0, kImage);  // older than everything waiting while full: dropped at once
  EXPECT_EQ(a.counters().dropped_queue_full, 3u);
  for (int64_t t = 3; t <= 5; ++t) a.addDepth(t, kDepth), a.addMask(t, kMask);
  EXPECT_EQ(a.takeReady().size(), 3u);
}

TEST(FrameAssembler, RejectsStampsGoingBackwardsAndBadOdometry) {
  FrameAssembler a(WithOdometry());
  AddAll(a, 500, 0.0);
  ASSERT_EQ(a.takeReady().size(), 1u);
  a.addColour(400, kImage);
  EXPECT_EQ(a.counters().rejected_invalid, 1u);
  EXPECT_NE(a.counters().last_rejection.find("stamps went backwards"), std::string::npos);
  StampedPose nan_pose = PoseAt(std::nan(""));
  a.addOdometry(600, nan_pose);
  EXPECT_EQ(a.counters().rejected_invalid, 2u);
  EXPECT_NE(a.counters().last_rejection.find("not finite"), std::string::npos);
  AssemblerParams no_timeout;
  no_timeout.timeout_ns = 0;
  EXPECT_THROW(FrameAssembler{no_timeout}, std::invalid_argument);
  AssemblerParams no_silence;
  no_silence.silence_timeout_ns = 0;
  EXPECT_THROW(FrameAssembler{no_silence}, std::invalid_argument);
}

}  // namespace
}  // namespace dslam
