#include "simulation/scene_builder.h"

#include <gtest/gtest.h>

#include "simulation/scenarios.h"

namespace dslam {
namespace {

std::vector<SE3> StraightPath(int frames, double step_m) {
  std::vector<SE3> path;
  for (int k = 0; k < frames; ++k) path.push_back(SE3(Mat3::Identity(), Vec3(0.0, 0.0, step_m * k)));
  return path;
}

TEST(SceneBuilder, RoadAndFacadesRunAlongThePathAndPastItsEnd) {
  StaticWorldOptions o;
  const auto quads = StaticWorldAlongPath(StraightPath(11, 2.0), o);  // 20 m
  ASSERT_FALSE(quads.empty());
  double z_min = 1e9, z_max = -1e9;
  int road = 0;
  for (const StaticQuad& q : quads)
    for (const Vec3& c : q.corners_world) {
      z_min = std::min(z_min, c.z());
      z_max = std::max(z_max, c.z());
      EXPECT_LE(std::abs(c.x()), o.road_half_width_m + 1e-9);
      EXPECT_GE(c.y(), o.camera_height_m - o.facade_height_m - 1e-9);  // nothing above the facades
      EXPECT_LE(c.y(), o.camera_height_m + 1e-9);                      // nothing below the road
    }
  for (const StaticQuad& q : quads) {
    bool flat = true;
    for (const Vec3& c : q.corners_world) flat &= std::abs(c.y() - o.camera_height_m) < 1e-9;
    road += flat;
  }
  EXPECT_LT(z_min, 0.0);            // behind the first camera
  EXPECT_GT(z_max, 20.0 + 60.0 - o.segment_m);  // and 60 m past the last
  EXPECT_GE(road, (20 + 60) / 4);   // a road piece every segment
}

TEST(SceneBuilder, AStillCameraGetsOneStationAndAnEmptyPathNone) {
  StaticWorldOptions o;
  const auto still = StaticWorldAlongPath(StraightPath(30, 0.0), o);
  const auto one = StaticWorldAlongPath(StraightPath(1, 0.0), o);
  EXPECT_EQ(still.size(), one.size());
  EXPECT_TRUE(StaticWorldAlongPath({}, o).empty());
}

TEST(SceneBuilder, ASimulatedSequenceKeepsItsBoxesAndLeavesOutOtherShapes) {
  ScenarioOptions opt;
  opt.num_frames = 10;
  const Sequence city = MakeScenario("city", opt);
  const Scene scene = SceneFromSequence(city);
  EXPECT_EQ(scene.T_world_camera.size(), 10u);
  int boxes = 0;
  for (const auto& [id, o] : city.gt.objects) boxes += o.box_lwh.has_value();
  ASSERT_GT(boxes, 0);
  ASSERT_EQ(static_cast<int>(scene.objects.size()), boxes);
  for (const SceneObject& obj : scene.objects) {
    const ObjectGroundTruth& gt = city.gt.objects.at(obj.object_id);
    EXPECT_DOUBLE_EQ(obj.l, gt.box_lwh->x());
    EXPECT_DOUBLE_EQ(obj.h, gt.box_lwh->z());
    EXPECT_EQ(obj.L_world_object.size(), gt.L_world_object.size());
  }
  const Sequence paper = MakeScenario("paper", opt);  // an ellipsoid, no box
  EXPECT_TRUE(SceneFromSequence(paper).objects.empty());
}

TEST(SceneBuilder, KittiBoxesArePlacedInTheWorldThroughTheirCamera) {
  KittiGroundTruthSequence gt;
  gt.name = "test";
  gt.T_world_camera = {SE3::Identity(), SE3(Mat3::Identity(), Vec3(0.0, 0.0, 1.0))};
  KittiObjectTrack car;
  car.object_id = 4;
  car.h = 1.5, car.w = 1.7, car.l = 4.0;
  car.T_camera_object[1] = SE3(Mat3::Identity(), Vec3(2.0, 1.6, 10.0));
  gt.objects[4] = car;
  const Scene scene = SceneFromKitti(gt);
  ASSERT_EQ(scene.objects.size(), 1u);
  EXPECT_EQ(scene.objects[0].object_id, 4);
  EXPECT_TRUE(scene.objects[0].L_world_object.at(1).translation().isApprox(Vec3(2.0, 1.6, 11.0), 1e-12));
  EXPECT_FALSE(scene.static_quads.empty());
}

}  // namespace
}  // namespace dslam
