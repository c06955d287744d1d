#include "pipeline/stage_latency.h"

#include <cmath>
#include <map>
#include <random>

#include <gtest/gtest.h>

namespace dslam {
namespace {

TEST(LatencyHistogram, QuantilesAreWithinHalfAPercentOfTheSamples) {
  LatencyHistogram h;
  EXPECT_EQ(h.quantile(0.5), 0.0);  // no samples
  std::vector<double> samples;
  std::mt19937 rng(3);
  std::lognormal_distribution<double> ms(std::log(30.0), 0.5);
  for (int i = 0; i < 5000; ++i) samples.push_back(ms(rng));
  for (double s : samples) h.add(s);
  std::sort(samples.begin(), samples.end());
  EXPECT_EQ(h.count(), 5000u);
  for (double q : {0.5, 0.9, 0.99}) {
    const double exact = samples[static_cast<size_t>(std::ceil(q * samples.size())) - 1];
    EXPECT_NEAR(h.quantile(q), exact, 0.006 * exact) << "q " << q;
  }
  EXPECT_EQ(h.max(), samples.back());
  EXPECT_LE(h.quantile(1.0), h.max());
}

TEST(LatencyHistogram, ExtremesStayBoundedAndNonFiniteIsIgnored) {
  LatencyHistogram h;
  h.add(-3.0);  // a clock step backwards counts as 0
  h.add(1e9);   // beyond the last bin: counted in it, the maximum exact
  h.add(std::nan(""));
  EXPECT_EQ(h.count(), 2u);
  EXPECT_EQ(h.max(), 1e9);
  EXPECT_LE(h.quantile(0.0), 0.01);
  EXPECT_GT(h.quantile(1.0), 5e5);
}

TEST(StageLatency, EachStageIsTheSpanBetweenItsTimesAndOnlyRecordedStagesAreReported) {
  StageLatency latency;
  for (int i = 0; i < 10; ++i) {
    FrameTiming t;
    const int64_t ms = 1'000'000;
    t.received_ns = 1000 * ms;
    t.decode_ms = 2.0;
    t.assembled_ns = t.received_ns + 5 * ms;
    t.frontend_start_ns = t.assembled_ns + 1 * ms;
    t.frontend_end_ns = t.frontend_start_ns + (30 + i) * ms;  // 30 .. 39 ms
    t.backend_start_ns = t.frontend_end_ns;                    // no wait
    t.backend_end_ns = t.backend_start_ns + 15 * ms;
    t.published_ns = t.backend_end_ns + 2 * ms;
    latency.add(t, i == 0 ? 80.0 : -1.0);
  }
  const std::vector<StageLatencySummary> s = latency.summary();
  std::map<std::string, StageLatencySummary> by_stage;
  for (const auto& stage : s) by_stage[stage.stage] = stage;
  ASSERT_EQ(s.size(), 9u);
  EXPECT_EQ(s.front().stage, "input");
  EXPECT_EQ(s.back().stage, "capture");
  EXPECT_NEAR(by_stage["input"].median_ms, 5.0, 0.03);
  EXPECT_NEAR(by_stage["decode"].median_ms, 2.0, 0.01);
  EXPECT_NEAR(by_stage["frontend_wait"].median_ms, 1.0, 0.01);
  EXPECT_NEAR(by_stage["frontend"].median_ms, 34.0, 0.2);  // the 5th of 30..39
  EXPECT_NEAR(by_stage["frontend"].p99_ms, 39.0, 0.2);
  EXPECT_EQ(by_stage["frontend"].max_ms, 39.0);
  EXPECT_NEAR(by_stage["backend_wait"].median_ms, 0.0, 0.01);
  EXPECT_NEAR(by_stage["backend"].median_ms, 15.0, 0.08);
  EXPECT_NEAR(by_stage["publish"].median_ms, 2.0, 0.01);
  EXPECT_NEAR(by_stage["total"].median_ms, 5 + 1 + 34 + 15 + 2, 0.3);
  EXPECT_EQ(by_stage["capture"].frames, 1u);
  EXPECT_EQ(by_stage["total"].frames, 10u);

  // A run's frames have no decode time and no capture stamp of this host: those stages are left out.
  StageLatency run;
  FrameTiming t;
  t.received_ns = 1;
  t.assembled_ns = t.frontend_start_ns = t.frontend_end_ns = t.backend_start_ns = t.backend_end_ns = t.published_ns = 2;
  run.add(t);
  for (const auto& stage : run.summary()) EXPECT_TRUE(stage.stage != "decode" && stage.stage != "capture") << stage.stage;
  EXPECT_EQ(run.summary().size(), 7u);

  const std::string line = FormatLatencyLine(s);
  EXPECT_NE(line.find(", frontend 34."), std::string::npos) << line;  // median/p99 to 0.1 ms, within 0.5 %
  EXPECT_NE(line.find("/39.0, backend_wait"), std::string::npos) << line;
  const nlohmann::json json = LatencyJson(s);
  EXPECT_EQ(json["backend"]["frames"], 10);
  EXPECT_NEAR(json["frontend"]["p99_ms"].get<double>(), 39.0, 0.2);
}

}  // namespace
}  // namespace dslam
