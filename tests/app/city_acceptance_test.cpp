// The `city` scenario: what `dslam sim --scenario city` must show.
#include <gtest/gtest.h>

#include "pipeline/run_sequence.h"
#include "simulation/scenarios.h"

namespace dslam {
namespace {

RunConfig CityConfig(const std::string& schedule) {
  RunConfig config;
  config.backend.default_mode = ParseMotionMode(ScenarioDefaultMotionMode("city"));
  config.backend.schedule = ParseSchedule(schedule);
  return config;
}

TEST(CityScenario, OursBeatsBothBaselinesAndHandlesStoppingAndReturningCars) {
  const Sequence seq = MakeScenario("city", ScenarioOptions{});
  const MethodOutcomes outcomes = RunSequence(seq, CityConfig("batch"));
  const auto& ours = outcomes.at(Method::kOurs).metrics;
  const auto& static_only = outcomes.at(Method::kStaticOnly).metrics;
  const auto& slam_mot = outcomes.at(Method::kSlamMot).metrics;
  std::cout << FormatMetricsTable(outcomes, "city, seed 1, batch");
  EXPECT_LT(*ours.camera.rte_pct, *static_only.camera.rte_pct);
  EXPECT_LT(*ours.objects->omte_pct, *slam_mot.objects->omte_pct);
  EXPECT_GE(*ours.objects->object_coverage, 0.95);

  const auto& motions = outcomes.at(Method::kOurs).result.estimate.object_motions;
  // The stopping car: dynamic while it drives, static once parked.
  std::vector<const ObjectMotionEstimate*> stopping;
  for (const auto& m : motions)
    if (m.object_id == kCityStopping) stopping.push_back(&m);
  ASSERT_GT(stopping.size(), 20u);
  EXPECT_TRUE(stopping.front()->is_dynamic);
  for (size_t i = stopping.size() - 5; i < stopping.size(); ++i) EXPECT_FALSE(stopping[i]->is_dynamic);
  EXPECT_NEAR(stopping.back()->speed_mps, 0.0, 1e-12);
  // The hidden car keeps its id: estimates before and after the occlusion, none during.
  int before = 0, during = 0, after = 0;
  for (const auto& m : motions) {
    if (m.object_id != kCityOccluded) continue;
    if (m.frame < kCityOcclusionBegin) ++before;
    else if (m.frame <= kCityOcclusionEnd) ++during;  // frame End has no predecessor in view
    else ++after;
  }
  EXPECT_GT(before, 20);
  EXPECT_EQ(during, 0);
  EXPECT_GT(after, 20);
}

TEST(CityScenario, SlidingWindowStaysWithinTenPercentOfBatch) {
  const Sequence seq = MakeScenario("city", ScenarioOptions{});
  RunSequenceOptions ours_only;
  ours_only.methods = {Method::kOurs};
  const auto batch = RunSequence(seq, CityConfig("batch"), ours_only).at(Method::kOurs).metrics;
  const auto window = RunSequence(seq, CityConfig("window:10"), ours_only).at(Method::kOurs).metrics;
  std::cout << "city RTE batch " << *batch.camera.rte_pct << " % window " << *window.camera.rte_pct << " %; OMTE batch "
            << *batch.objects->omte_pct << " % window " << *window.objects->omte_pct << " %\n";
  EXPECT_LE(*window.camera.rte_pct, 1.1 * *batch.camera.rte_pct);
  EXPECT_LE(*window.objects->omte_pct, 1.1 * *batch.objects->omte_pct);
}

}  // namespace
}  // namespace dslam
