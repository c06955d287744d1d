#include "plugin/object_markers.h"

#include <gtest/gtest.h>

namespace dslam {
namespace {

TEST(ObjectMarkers, ClearThenASphereATextAndForAMovingObjectAnArrowAlongItsVelocity) {
  FrameEstimate e;
  e.t_ns = 2'500'000'000;
  ObjectMotionEstimate moving, standing;
  moving.object_id = 7, moving.is_dynamic = true, moving.speed_mps = 10.0;
  moving.H_world = SE3(Eigen::Quaterniond::Identity(), Vec3(1.0, 0.0, 0.0));
  moving.centroid_prev_world = Vec3(4.0, 0.0, 20.0);
  moving.velocity_world_per_frame = Vec3(1.0, 0.0, 0.0);  // 10 m/s at 10 Hz
  standing.object_id = 1003, standing.is_dynamic = false;
  standing.centroid_prev_world = Vec3(-9.0, 1.0, 12.0);
  e.object_motions = {moving, standing};
  const auto array = ObjectMarkers(e, 10.0);
  const auto& m = array.markers();
  ASSERT_EQ(m.size(), 6u);  // clear; moving: sphere, arrow, text; standing: sphere, text
  EXPECT_EQ(m[0].action(), kMarkerDeleteAll);
  for (const auto& marker : m) {
    EXPECT_EQ(marker.header().frame_id(), "world");
    EXPECT_EQ(marker.header().stamp().sec(), 2);
    EXPECT_EQ(marker.header().stamp().nanosec(), 500'000'000u);
  }
  EXPECT_EQ(m[1].type(), kMarkerSphere);
  EXPECT_EQ(m[1].id(), 7);
  EXPECT_DOUBLE_EQ(m[1].pose().position().x(), 5.0);  // the centroid moved by H into the frame
  EXPECT_GT(m[1].color().r(), m[1].color().g());      // red: moving
  EXPECT_EQ(m[2].type(), kMarkerArrow);
  ASSERT_EQ(m[2].points().size(), 2u);
  EXPECT_DOUBLE_EQ(m[2].points()[1].x() - m[2].points()[0].x(), 10.0);  // 1 s of travel
  EXPECT_EQ(m[3].type(), kMarkerText);
  EXPECT_EQ(m[3].text(), "7: 36 km/h");
  EXPECT_LT(m[3].pose().position().y(), m[1].pose().position().y());  // above (y down)
  EXPECT_EQ(m[4].type(), kMarkerSphere);
  EXPECT_FLOAT_EQ(m[4].color().r(), m[4].color().g());  // grey: standing
  EXPECT_EQ(m[5].text(), "1003: standing");
  // Nothing estimated: the clear alone, so the last frame's objects disappear.
  EXPECT_EQ(ObjectMarkers(FrameEstimate{}, 10.0).markers().size(), 1u);
}

}  // namespace
}  // namespace dslam
