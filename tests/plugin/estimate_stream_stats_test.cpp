#include "plugin/estimate_stream_stats.h"

#include <gtest/gtest.h>

namespace dslam {
namespace {

ReceivedEstimate At(int64_t stamp_ms, int64_t received_ms, const std::string& writer = "a") {
  ReceivedEstimate e;
  e.stamp_ns = stamp_ms * 1'000'000;
  e.received_unix_ns = received_ms * 1'000'000;
  e.writer = writer;
  return e;
}

TEST(EstimateStreamStats, CountsRepeatsGapsOrderWritersSilenceAndLatency) {
  EstimateStreamStats stats(10.0);
  const int64_t t0 = 1'800'000'000'000;  // a stamp of "now" (ms since the epoch)
  EXPECT_NEAR(stats.add(At(t0, t0 + 50)), 50.0, 1e-9);
  stats.add(At(t0 + 100, t0 + 160));
  stats.add(At(t0 + 100, t0 + 170, "b"));  // the same frame again, from a second writer
  stats.add(At(t0 + 400, t0 + 480));       // frames at +200 and +300 never arrived
  stats.add(At(t0 + 350, t0 + 1480));      // late and out of order; a 1 s silence before it
  EXPECT_EQ(stats.received(), 5u);
  EXPECT_EQ(stats.distinctStamps(), 4u);
  EXPECT_EQ(stats.repeated(), 1u);
  EXPECT_EQ(stats.missingFrames(), 2u);
  EXPECT_EQ(stats.wentBack(), 1u);
  EXPECT_NEAR(stats.longestSilenceMs(), 1000.0, 1e-6);
  EXPECT_EQ(stats.perWriter().at("a"), 4u);
  EXPECT_EQ(stats.perWriter().at("b"), 1u);
  EXPECT_EQ(stats.captureLatency().count(), 5u);
  EXPECT_NEAR(stats.captureLatency().max(), 1130.0, 1e-6);
  const auto json = stats.json();
  EXPECT_EQ(json["frames"], 4);
  EXPECT_EQ(json["writers"]["b"], 1);
  EXPECT_NE(stats.line().find("5 estimates (4 frames) from 2 writers, 1 repeated"), std::string::npos) << stats.line();
}

TEST(EstimateStreamStats, StampsOfAnotherClockHaveNoLatency) {
  EstimateStreamStats stats(10.0);
  EXPECT_LT(stats.add(At(5'000, 1'800'000'000'000)), 0.0);  // dataset stamps: seconds from the start
  EXPECT_EQ(stats.captureLatency().count(), 0u);
  EXPECT_EQ(stats.line().find("latency"), std::string::npos);
  EXPECT_THROW(EstimateStreamStats(0.0), std::invalid_argument);
}

}  // namespace
}  // namespace dslam
