// The LiDAR-only reference on a synthetic drive: scan registration, cluster tracks and their speeds,
// and a run compared against it.
#include "lidar/lidar_reference.h"

#include <gtest/gtest.h>

#include "lidar/lidar_comparison.h"
#include "lidar/scan_registration.h"
#include "support/synthetic_lidar.h"

namespace dslam {
namespace {
using test::BoxOnGround;
using test::SceneBox;

// Static structure along a street: walls on both sides, a building across its end, and a short wall by a
// bus stop (as long as a car: a cluster of an object's size, left out of the ego-motion like one).
std::vector<SceneBox> Street() {
  return {BoxOnGround(-9.0f, 30.0f, 0.5f, 3.0f, 60.0f), BoxOnGround(9.5f, 30.0f, 0.5f, 3.0f, 60.0f),
          BoxOnGround(0.0f, 45.0f, 30.0f, 10.0f, 2.0f), BoxOnGround(6.0f, 25.0f, 0.3f, 2.0f, 4.0f)};
}

// The scene as the sensor sees it after driving `ego_z` metres forward (camera frame of that moment).
std::vector<SceneBox> Seen(const std::vector<SceneBox>& world, float ego_z) {
  std::vector<SceneBox> out = world;
  for (SceneBox& b : out) b.lo.z() -= ego_z, b.hi.z() -= ego_z;
  return out;
}

TEST(ScanRegistration, RecoversAKnownMotionOfAStreetScan) {
  const test::SyntheticLidar lidar;
  const std::vector<Eigen::Vector3f> before = lidar.scan(Seen(Street(), 0.0f)), after = lidar.scan(Seen(Street(), 0.3f));
  // Points of `after` map into `before` by a forward shift of 0.3 m.
  const Registration r = RegisterPoints(after, before, Eigen::Isometry3d::Identity(), ScanRegistrationParams{});
  EXPECT_TRUE(r.converged);
  EXPECT_NEAR(r.T_target_source.translation().z(), 0.3, 0.03);
  EXPECT_NEAR(r.T_target_source.translation().x(), 0.0, 0.02);
  EXPECT_LT(Eigen::AngleAxisd(r.T_target_source.linear()).angle(), 0.2 * M_PI / 180.0);
  EXPECT_THROW(RegisterPoints({}, before, Eigen::Isometry3d::Identity(), ScanRegistrationParams{}), std::invalid_argument);
}

struct Drive {
  LidarReference reference;
  std::vector<SE3> truth;  // T_world_camera
};

// 20 scans at 10 Hz: the ego car at 2 m/s, a car ahead pulling away at 2 m/s faster (4 m/s), a parked car.
Drive DriveDownTheStreet() {
  const test::SyntheticLidar lidar;
  LidarReferenceParams params;
  PinholeCamera camera;
  LidarReferenceBuilder builder(params, camera);
  Drive d;
  for (int k = 0; k < 20; ++k) {
    const float ego = 0.2f * k;
    std::vector<SceneBox> world = Street();
    world.push_back(BoxOnGround(0.0f, 9.0f + 0.4f * k, 1.8f, 1.5f, 4.2f));  // moving car
    world.push_back(BoxOnGround(-6.0f, 14.0f, 1.8f, 1.5f, 4.2f));           // parked car
    builder.add(lidar.scan(Seen(world, ego)), lidar.origin, Eigen::Vector3f(0.0f, -1.0f, 0.0f));
    d.truth.push_back(SE3(Mat3::Identity(), Vec3(0.0, 0.0, ego)));
  }
  d.reference = builder.finish();
  return d;
}

TEST(LidarReference, EgoMotionAndEachClustersSpeedFromTheScansAlone) {
  const Drive d = DriveDownTheStreet();
  ASSERT_EQ(d.reference.T_world_camera.size(), 20u);
  EXPECT_NEAR(d.reference.T_world_camera.back().translation().z(), 3.8, 0.1);
  EXPECT_NEAR(d.reference.T_world_camera.back().translation().x(), 0.0, 0.05);
  // Two tracks through all 20 scans: the moving car (4 m/s) and the parked one (0 m/s).
  std::map<int, std::vector<const LidarTrackSample*>> tracks;
  for (const LidarTrackSample& s : d.reference.samples) tracks[s.track_id].push_back(&s);
  int moving = 0, parked = 0;
  for (const auto& [id, samples] : tracks) {
    if (samples.size() < 15) continue;
    const LidarTrackSample& mid = *samples[samples.size() / 2];
    ASSERT_TRUE(mid.has_speed);
    if (mid.centroid_camera.x() > 4.0) continue;  // the bus stop's wall, on the right
    if (std::abs(mid.centroid_camera.x()) < 3.0) {
      EXPECT_NEAR(mid.speed_mps, 4.0, 0.3) << "the car ahead";
      ++moving;
    } else {
      EXPECT_LT(mid.speed_mps, 0.3) << "the parked car";
      ++parked;
    }
  }
  EXPECT_EQ(moving, 1);
  EXPECT_EQ(parked, 1);
}

TEST(LidarComparison, ScoresTheCameraPathAndEachVehiclesSpeedAgainstTheReference) {
  const Drive d = DriveDownTheStreet();
  // A run whose camera is 5 % short every frame, with the car ahead at the right speed in every frame but
  // two, and the parked car called moving once.
  std::vector<SE3> run;
  for (const SE3& T : d.truth) run.push_back(SE3(Mat3::Identity(), 0.95 * T.translation()));
  std::vector<RunObjectRow> rows;
  for (const LidarTrackSample& s : d.reference.samples) {
    if (!s.has_speed || s.frame == 5 || s.frame == 6) continue;
    if (s.centroid_camera.x() > 4.0) continue;  // the bus stop's wall, on the right
    const bool ahead = std::abs(s.centroid_camera.x()) < 3.0;
    const bool wrong = !ahead && s.frame == 10;
    rows.push_back({s.frame, ahead ? 1 : 2, ahead || wrong, ahead ? 4.1 : (wrong ? 1.5 : 0.0),
                    s.centroid_camera + Vec3(0.3, 0.0, -0.5)});
  }
  rows.push_back({8, 3, true, 3.0, Vec3(0.0, -1.0, 30.0)});  // a "moving object" where there is no cluster
  const LidarCheckReport r = CompareWithLidar(d.reference, run, rows, LidarCheckParams{});
  EXPECT_NEAR(r.path_length_m, 3.8, 0.15);
  EXPECT_NEAR(r.end_error_pct, 5.0, 1.5);
  EXPECT_NEAR(r.rte_pct, 5.0, 2.5);
  // The two cars, and the bus stop's wall (clusters are class-agnostic): the run gave it no speed.
  std::vector<LidarCheckReport::Vehicle> cars;
  for (const auto& v : r.vehicles) {
    EXPECT_EQ(v.frames, 19);  // every scan but the first has a speed
    if (v.frames_with_speed > 0) cars.push_back(v);
  }
  ASSERT_EQ(cars.size(), 2u);
  for (const auto& v : cars) {
    EXPECT_EQ(v.frames_with_speed, 17);
    ASSERT_TRUE(v.median_speed_difference_mps);
    EXPECT_LT(*v.median_speed_difference_mps, 0.4);
  }
  const int parked = cars[0].median_lidar_speed_mps < 1.0 ? 0 : 1;
  EXPECT_EQ(cars[parked].moving_while_standing, 1);
  EXPECT_EQ(cars[1 - parked].moving_while_standing, 0);
  EXPECT_EQ(r.moving_rows_without_cluster, 1);
  EXPECT_EQ(r.moving_rows_on_standing, 1);
  EXPECT_THROW(CompareWithLidar(d.reference, {SE3()}, rows, LidarCheckParams{}), std::invalid_argument);
}

}  // namespace
}  // namespace dslam

namespace dslam {
namespace {

TEST(LidarReference, AScanWithNothingButGroundIsAClearErrorNamingIt) {
  const test::SyntheticLidar lidar;
  LidarReferenceBuilder builder(LidarReferenceParams{}, PinholeCamera{});
  builder.add(lidar.scan({}), lidar.origin, Eigen::Vector3f(0.0f, -1.0f, 0.0f));
  try {
    builder.add(lidar.scan({}), lidar.origin, Eigen::Vector3f(0.0f, -1.0f, 0.0f));
    FAIL() << "registered a scan of bare ground";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("LiDAR scan 1"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace dslam
