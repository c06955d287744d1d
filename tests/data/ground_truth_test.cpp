#include "data/ground_truth.h"

#include <gtest/gtest.h>

namespace dslam {
namespace {

TEST(GroundTruth, TruncatedToTheFramesARunReachedKeepsNothingBeyondThem) {
  GroundTruth gt;
  gt.T_world_camera.assign(6, SE3());
  ObjectGroundTruth early, late;
  early.object_id = 1;
  late.object_id = 2;
  for (int k = 0; k < 6; ++k) {
    early.L_world_object[k] = SE3();
    early.centroid_world[k] = Vec3(k, 0.0, 10.0);
    early.observed_frames.insert(k);
  }
  early.measurable_frames = std::set<int>{1, 2, 5};
  late.L_world_object[4] = SE3();  // exists only from frame 4 on
  late.centroid_world[4] = Vec3::Zero();
  gt.objects[1] = early;
  gt.objects[2] = late;

  TruncateGroundTruth(3, &gt);
  EXPECT_EQ(gt.T_world_camera.size(), 3u);
  ASSERT_EQ(gt.objects.size(), 1u);  // object 2 had no frame among the first three
  const ObjectGroundTruth& o = gt.objects.at(1);
  EXPECT_EQ(o.L_world_object.size(), 3u);
  EXPECT_EQ(o.centroid_world.rbegin()->first, 2);
  EXPECT_EQ(o.observed_frames, (std::set<int>{0, 1, 2}));
  EXPECT_EQ(*o.measurable_frames, (std::set<int>{1, 2}));
  TruncateGroundTruth(10, &gt);  // more frames than it has: unchanged
  EXPECT_EQ(gt.T_world_camera.size(), 3u);
}

}  // namespace
}  // namespace dslam
