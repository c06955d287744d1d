#include "lidar/point_cloud_segmentation.h"

#include <gtest/gtest.h>

#include <cstdlib>

#include "data/runtime_module.h"
#include "support/synthetic_lidar.h"

namespace dslam {
namespace {
using test::BoxOnGround;
using test::SceneBox;

// Which cluster (index) holds most points inside `box`, or -1.
int ClusterIn(const LidarSegmentation& seg, const std::vector<Eigen::Vector3f>& points, const SceneBox& box) {
  int best = -1;
  size_t most = 0;
  for (size_t c = 0; c < seg.objects.size(); ++c) {
    size_t inside = 0;
    for (int i : seg.objects[c].point_indices)
      inside += (points[i].array() >= box.lo.array() - 0.05f).all() && (points[i].array() <= box.hi.array() + 0.05f).all();
    if (inside > most) most = inside, best = static_cast<int>(c);
  }
  return best;
}

// PCL is in a module of its own (lidar/pcl_module.h), mapped when the first scan is segmented; bad
// parameters are refused before it is loaded. Checked in a process of its own (gtest's "threadsafe" death
// tests start the test binary afresh): another test may have loaded it already.
int PclLoadOrder() {
  if (RuntimeModuleLoaded("dslam_pcl")) return 1;
  LidarSegmentationParams bad;
  bad.cluster_tolerance_m = 0.0;
  try {
    SegmentLidarObjects({}, bad);
    return 2;
  } catch (const std::invalid_argument&) {
  }
  if (RuntimeModuleLoaded("dslam_pcl")) return 3;
  const LidarSegmentation seg =
      SegmentLidarObjects(test::SyntheticLidar{}.scan({BoxOnGround(-2.0f, 10.0f, 1.8f, 1.5f, 4.2f)}), {});
  if (seg.objects.size() != 1) return 4;
  return RuntimeModuleLoaded("dslam_pcl") ? 0 : 5;
}

TEST(PointCloudSegmentation, PclIsLoadedOnFirstUseOnly) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  // 1, 3: loaded too early; 2: bad parameters accepted; 4: the car not found; 5: not loaded by the segmentation.
  EXPECT_EXIT(std::exit(PclLoadOrder()), ::testing::ExitedWithCode(0), "");
}

TEST(PointCloudSegmentation, FindsTheGroundAndEachObjectButNotWallsOrBridges) {
  const SceneBox car = BoxOnGround(-2.0f, 10.0f, 1.8f, 1.5f, 4.2f);
  const SceneBox truck = BoxOnGround(3.5f, 14.0f, 2.5f, 3.6f, 10.0f);
  const SceneBox pole = BoxOnGround(1.0f, 20.0f, 0.3f, 3.0f, 0.3f);  // seen between the car and the truck
  const SceneBox long_wall = BoxOnGround(-9.0f, 20.0f, 0.4f, 2.0f, 30.0f);
  const SceneBox kerb = BoxOnGround(7.0f, 12.0f, 0.3f, 0.4f, 6.0f);
  const std::vector<SceneBox> scene = {car, truck, pole, long_wall, kerb};
  std::vector<Eigen::Vector3f> points = test::SyntheticLidar{}.scan(scene);
  // The underside of a bridge 6 m above the road (a spinning LiDAR looks up only 2 degrees: as returns
  // from a sensor that sees it), 4 m wide, 10 m ahead.
  const SceneBox bridge{Eigen::Vector3f(-4.0f, 1.65f - 6.1f, 10.0f), Eigen::Vector3f(4.0f, 1.65f - 5.9f, 14.0f)};
  for (float x = -4.0f; x <= 4.0f; x += 0.2f)
    for (float z = 10.0f; z <= 14.0f; z += 0.2f) points.emplace_back(x, 1.65f - 6.0f, z);
  const LidarSegmentation seg = SegmentLidarObjects(points, LidarSegmentationParams{});

  ASSERT_TRUE(seg.ground_valid);
  EXPECT_NEAR(seg.ground_normal.y(), -1.0f, 1e-3f);
  EXPECT_NEAR(seg.ground_d, 1.65f, 0.02f);  // n . p + d = 0 with n = -y: d = ground_y
  EXPECT_GT(seg.ground.size(), 1000u);

  EXPECT_GE(seg.objects.size(), 3u) << "the car, the truck and the pole (an edge-on side may come apart)";
  const int c_car = ClusterIn(seg, points, car), c_truck = ClusterIn(seg, points, truck), c_pole = ClusterIn(seg, points, pole);
  EXPECT_GE(c_car, 0);
  EXPECT_GE(c_truck, 0);
  EXPECT_GE(c_pole, 0);
  EXPECT_NE(c_car, c_truck);
  EXPECT_EQ(c_car, 0) << "nearest first";
  // The car's cluster holds its points and no other's.
  for (int i : seg.objects[c_car].point_indices) EXPECT_LT((points[i] - Eigen::Vector3f(-2.0f, 0.9f, 10.0f)).norm(), 3.0f);
  // The truck's top is above the LiDAR's highest beam (+2 degrees): 2.2 m up at its front, 14 - 5 m away.
  EXPECT_NEAR(seg.objects[c_truck].top_height_m, 2.2f, 0.2f);
  // Neither the wall (30 m long), the kerb (40 cm high) nor the bridge (above a truck) is an object.
  EXPECT_EQ(ClusterIn(seg, points, long_wall), -1);
  EXPECT_EQ(ClusterIn(seg, points, kerb), -1);
  EXPECT_EQ(ClusterIn(seg, points, bridge), -1);
}

TEST(PointCloudSegmentation, TwoCarsFartherApartThanTheToleranceStayTwoObjects) {
  // Side by side, 1.2 m apart. The sides facing each other are seen edge-on and sampled sparsely: they may
  // come out as small clusters of their own, but no cluster holds points of both cars.
  const std::vector<SceneBox> scene = {BoxOnGround(-1.5f, 9.0f, 1.8f, 1.5f, 4.0f), BoxOnGround(1.5f, 9.0f, 1.8f, 1.5f, 4.0f)};
  const std::vector<Eigen::Vector3f> points = test::SyntheticLidar{}.scan(scene);
  LidarSegmentationParams params;
  const LidarSegmentation seg = SegmentLidarObjects(points, params);
  ASSERT_GE(seg.objects.size(), 2u);
  for (const LidarObjectCluster& c : seg.objects) {
    int left = 0, right = 0;
    for (int i : c.point_indices) (points[i].x() < 0.0f ? left : right)++;
    EXPECT_TRUE(left == 0 || right == 0) << left << " left and " << right << " right";
  }
  // The two largest clusters are the cars' faces towards the sensor, one on each side.
  EXPECT_LT(seg.objects[0].centroid_camera.x() * seg.objects[1].centroid_camera.x(), 0.0f);
  params.cluster_tolerance_m = 1.5;  // wider than the gap: one cluster
  EXPECT_EQ(SegmentLidarObjects(points, params).objects.size(), 1u);
}

TEST(PointCloudSegmentation, ATruckSeenAboveANearerCarIsStillAnObject) {
  const std::vector<SceneBox> scene = {BoxOnGround(0.0f, 8.0f, 1.8f, 1.5f, 4.0f), BoxOnGround(0.5f, 16.0f, 2.5f, 3.0f, 5.0f)};
  EXPECT_EQ(SegmentLidarObjects(test::SyntheticLidar{}.scan(scene), LidarSegmentationParams{}).objects.size(), 2u);
}

TEST(PointCloudSegmentation, PointsOutOfViewAndNonFinitePointsAreIgnored) {
  std::vector<Eigen::Vector3f> points = test::SyntheticLidar{}.scan({BoxOnGround(0.0f, 8.0f, 1.8f, 1.5f, 4.0f)});
  points.push_back(Eigen::Vector3f(std::nanf(""), 0.0f, 5.0f));
  std::vector<bool> in_view(points.size(), true);
  EXPECT_EQ(SegmentLidarObjects(points, LidarSegmentationParams{}, in_view).objects.size(), 1u);
  for (size_t i = 0; i < points.size(); ++i) in_view[i] = points[i].z() > 20.0f;  // the car is not in view
  EXPECT_EQ(SegmentLidarObjects(points, LidarSegmentationParams{}, in_view).objects.size(), 0u);
  in_view.pop_back();
  EXPECT_THROW(SegmentLidarObjects(points, LidarSegmentationParams{}, in_view), std::invalid_argument);
}

TEST(PointCloudSegmentation, ParametersOutOfRangeAreRefusedByName) {
  LidarSegmentationParams p;
  p.cluster_tolerance_m = 0.0;
  try {
    p.validate();
    FAIL() << "accepted a zero tolerance";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("cluster_tolerance_m"), std::string::npos);
  }
  p = LidarSegmentationParams{};
  p.ground_max_tilt_deg = 60.0;
  EXPECT_THROW(p.validate(), std::invalid_argument);
  p = LidarSegmentationParams{};
  p.min_cluster_points = 2;
  EXPECT_THROW(p.validate(), std::invalid_argument);
  p = LidarSegmentationParams{};
  p.max_range_m = std::numeric_limits<double>::infinity();
  EXPECT_THROW(p.validate(), std::invalid_argument);
}

}  // namespace
}  // namespace dslam
