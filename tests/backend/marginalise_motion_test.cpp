#include "backend/marginalisation.h"

// An object motion leaving the window: a motion per frame (smoothed) is final when its frame leaves the
// object window and is held at that value in the smoothness factor to the next motion; an object's one
// motion for its whole track (constant) stays while the track lasts, its transitions final only with it.

#include <gtest/gtest.h>

#include <map>
#include <set>

#include "backend/graph_builder.h"
#include "support/city_graph.h"
#include "support/final_estimates.h"

namespace dslam {
namespace {

using test::CityGraph;

TEST(MarginaliseMotion, ALeavingMotionIsFinalAndHeldAtItsValueInTheSmoothnessToTheNext) {
  BackendParams params;
  params.default_mode = MotionMode::kSmoothed;
  FactorGraph graph = CityGraph(6, params);
  // The motions into frame 2 and their values, and the smoothness factors from them into frame 3.
  std::map<int, MotionVariable> into_2;
  for (const auto& [id, motion] : graph.motions)
    if (motion.first_frame == 2 && motion.last_frame == 2) into_2[id] = motion;
  ASSERT_FALSE(into_2.empty());
  std::set<int> smoothed_from_2;
  for (const auto& s : graph.frame(3).smoothness)
    if (into_2.count(s.prev_motion_var)) smoothed_from_2.insert(s.curr_motion_var);
  ASSERT_FALSE(smoothed_from_2.empty());

  test::FinalEstimates sink;
  for (int m = 0; m <= 2; ++m) MarginaliseObjectFrame(params, 10.0, m, &graph, &sink);
  for (const auto& [id, motion] : into_2) EXPECT_FALSE(graph.motions.count(id)) << "motion " << id << " left";
  // Each motion into frame 2 went to the sink once, with the value it had.
  for (const auto& [id, motion] : into_2) {
    int reported = 0;
    for (const ObjectMotionEstimate& m : sink.motions)
      if (m.frame == 2 && m.object_id == motion.object_id) {
        ++reported;
        EXPECT_LT((m.H_world.matrix() - motion.worldMotion().matrix()).norm(), 1e-12) << "object " << motion.object_id;
      }
    EXPECT_EQ(reported, 1) << "object " << motion.object_id;
  }
  // In the smoothness factors into frame 3 the leaving motion is now a constant: its final value.
  int held = 0;
  for (const auto& s : graph.frame(3).smoothness) {
    if (!smoothed_from_2.count(s.curr_motion_var)) continue;
    EXPECT_EQ(s.prev_motion_var, -1);
    const auto it = std::find_if(into_2.begin(), into_2.end(), [&](const auto& kv) {
      return kv.second.object_id == graph.motions.at(s.curr_motion_var).object_id;
    });
    ASSERT_NE(it, into_2.end());
    EXPECT_EQ(PoseBlockMinus(s.prev_fixed.data(), it->second.H_anchor.data()).norm(), 0.0);
    EXPECT_TRUE(s.prev_fixed_anchor.isApprox(it->second.anchor_world, 0.0));
    ++held;
  }
  EXPECT_EQ(held, static_cast<int>(smoothed_from_2.size()));
}

TEST(MarginaliseMotion, AnObjectsOneMotionStaysWhileItsTrackLastsAndItsTransitionsLeaveWithIt) {
  BackendParams params;
  params.default_mode = MotionMode::kConstant;
  FactorGraph graph = CityGraph(6, params);
  std::map<int, int> motion_of_object;  // the track motions that last beyond frame 2
  for (const auto& [id, motion] : graph.motions)
    if (motion.last_frame > 2) motion_of_object[motion.object_id] = id;
  ASSERT_FALSE(motion_of_object.empty());

  test::FinalEstimates sink;
  for (int m = 0; m <= 2; ++m) MarginaliseObjectFrame(params, 10.0, m, &graph, &sink);
  for (const auto& [object, id] : motion_of_object) {
    EXPECT_TRUE(graph.motions.count(id)) << "object " << object << "'s motion stays";
    for (const ObjectMotionEstimate& m : sink.motions) EXPECT_NE(m.object_id, object) << "reported at " << m.frame;
    int kept = 0;
    for (const ObjectTransition& tr : graph.transitions) kept += tr.object_id == object && tr.frame <= 2;
    EXPECT_GT(kept, 0) << "object " << object << "'s early transitions wait for its motion";
  }
}

}  // namespace
}  // namespace dslam
