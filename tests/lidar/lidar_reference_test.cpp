// The LiDAR-only reference on a synthetic drive: scan registration, cluster tracks and their speeds,
// and a run compared against it.
#include "lidar/lidar_reference.h"

#include <cstdio>

#include <gtest/gtest.h>

#include "lidar/lidar_comparison.h"
#include "lidar/scan_registration.h"
#include "support/synthetic_lidar.h"

namespace dslam {
namespace {
using test::BoxOnGround;
using test::SceneBox;

// Static structure along a street: walls on both sides, a long hedge along the left one (the top of
// something below the sensor: the ground is left out of the ego-motion, and walls alone would leave its
// height free), a building across its end, and a short wall by a bus stop (as long as a car: a cluster of an
// object's size, left out of the ego-motion like one).
std::vector<SceneBox> Street() {
  return {BoxOnGround(-9.0f, 30.0f, 0.5f, 3.0f, 60.0f), BoxOnGround(9.5f, 30.0f, 0.5f, 3.0f, 60.0f),
          BoxOnGround(-8.45f, 30.0f, 0.6f, 1.0f, 50.0f), BoxOnGround(0.0f, 45.0f, 30.0f, 10.0f, 2.0f),
          BoxOnGround(6.0f, 25.0f, 0.3f, 2.0f, 4.0f)};
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

// Where registering `after` onto `before` from `guess` puts the sensor's forward motion.
double ForwardMotion(const std::vector<Eigen::Vector3f>& after, const std::vector<Eigen::Vector3f>& before, double guess_z,
                     const ScanRegistrationParams& params) {
  Eigen::Isometry3d guess = Eigen::Isometry3d::Identity();
  guess.translation().z() = guess_z;
  return RegisterPoints(after, before, guess, params).T_target_source.translation().z();
}

TEST(ScanRegistration, TheReferencesSettingReachesTheSameMotionFromAStandstillOrAConstantVelocityStart) {
  // The reference starts each scan pair from the previous pair's motion; a registration that stops near
  // its start (as generalized ICP did on real scans) makes the path follow that guess.
  const test::SyntheticLidar lidar;
  const std::vector<Eigen::Vector3f> before = lidar.scan(Seen(Street(), 0.0f)), after = lidar.scan(Seen(Street(), 0.3f));
  const ScanRegistrationParams ego = EgoRegistration();
  const double from_still = ForwardMotion(after, before, 0.0, ego), from_faster = ForwardMotion(after, before, 0.55, ego);
  EXPECT_NEAR(from_still, 0.3, 0.02);
  EXPECT_NEAR(from_faster, 0.3, 0.02);
  EXPECT_NEAR(from_still, from_faster, 0.005);
}

TEST(ScanRegistration, KeepingTheClosestPairsLeavesAVehicleDrivingAlongsideOut) {
  // A long truck beside the sensor keeps its place in the sensor's frame (it drives at the same speed):
  // with every pair kept it holds the motion back; with the closest 70 % kept the walls win.
  const test::SyntheticLidar lidar;
  std::vector<SceneBox> before_scene = Seen(Street(), 0.0f), after_scene = Seen(Street(), 0.3f);
  const SceneBox truck = BoxOnGround(3.5f, 6.0f, 2.5f, 3.5f, 12.0f);
  before_scene.push_back(truck);
  after_scene.push_back(truck);
  const std::vector<Eigen::Vector3f> before = lidar.scan(before_scene), after = lidar.scan(after_scene);
  ScanRegistrationParams every_pair = EgoRegistration();
  every_pair.kept_pair_fraction = 1.0;
  const double pulled = ForwardMotion(after, before, 0.3, every_pair);
  const double trimmed = ForwardMotion(after, before, 0.3, EgoRegistration());
  std::printf("forward motion 0.3 m: every pair %.4f, closest 70 %% %.4f\n", pulled, trimmed);
  EXPECT_NEAR(trimmed, 0.3, 0.02);
  EXPECT_GT(std::abs(pulled - 0.3), 2.0 * std::abs(trimmed - 0.3));
}

TEST(ScanRegistration, RefusesSettingsItCannotHonour) {
  const std::vector<Eigen::Vector3f> points = {{0, 0, 1}, {1, 0, 1}, {0, 1, 1}, {1, 1, 2}};
  ScanRegistrationParams p;
  p.kept_pair_fraction = 0.0;
  EXPECT_THROW(RegisterPoints(points, points, Eigen::Isometry3d::Identity(), p), std::invalid_argument);
  p.kept_pair_fraction = 0.7;
  p.metric = RegistrationMetric::kGeneralized;  // PCL's generalized ICP keeps every pair
  EXPECT_THROW(RegisterPoints(points, points, Eigen::Isometry3d::Identity(), p), std::invalid_argument);
  p = ScanRegistrationParams{};
  p.normal_neighbours = 2;
  EXPECT_THROW(RegisterPoints(points, points, Eigen::Isometry3d::Identity(), p), std::invalid_argument);
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

TEST(LidarReference, ACarThatTheImagesEdgeCutsAsTheEgoCarPassesItStillStands) {
  // A parked car on the left, 7 m ahead at first: from frame 9 on the image's edge (40 degrees) cuts it.
  // Its points in view shrink towards the edge, and their centroid moves with the edge; its speed comes
  // from its points in the whole scan. (Its windowed speed is scored up to frame 13: later, the synthetic
  // LiDAR's own 60 degrees cut it too.)
  const test::SyntheticLidar lidar;
  LidarReferenceBuilder builder(LidarReferenceParams{}, PinholeCamera{});
  for (int k = 0; k < 20; ++k) {
    std::vector<SceneBox> world = Street();
    world.push_back(BoxOnGround(-3.5f, 7.0f, 1.8f, 1.5f, 4.2f));
    builder.add(lidar.scan(Seen(world, 0.2f * k)), lidar.origin, Eigen::Vector3f(0.0f, -1.0f, 0.0f));
  }
  const LidarReference reference = builder.finish();
  int scored = 0, cut = 0;
  for (const LidarTrackSample& s : reference.samples) {
    if (!s.has_speed || s.frame > 13 || s.centroid_camera.x() > -2.0 || s.centroid_camera.x() < -5.0 ||
        s.centroid_camera.z() > 12.0)
      continue;  // the parked car only
    EXPECT_LT(s.speed_mps, 0.3) << "frame " << s.frame;
    ++scored;
    cut += s.box.x == 0;
  }
  EXPECT_GE(scored, 12);
  EXPECT_GE(cut, 3) << "the image's edge cuts it in the later frames";
}

TEST(LidarComparison, AVehicleIsScoredOnlyInFramesWhereTheCameraSeesIt) {
  Drive d = DriveDownTheStreet();
  LidarCheckParams params;
  params.image_width = 1242, params.image_height = 375;
  const size_t before = CompareWithLidar(d.reference, d.truth, {}, params).vehicles.size();
  // The parked car hidden (no pixels) from frame 5 on, or a sliver of 10 x 10 pixels (under 0.05 % of the
  // image): 4 frames of it are left, under the 10 a vehicle needs.
  for (const cv::Rect sliver : {cv::Rect(), cv::Rect(0, 100, 10, 10)}) {
    Drive hidden = d;
    for (LidarTrackSample& s : hidden.reference.samples)
      if (s.frame >= 5 && s.centroid_camera.x() < -3.0) s.box = sliver;
    EXPECT_EQ(CompareWithLidar(hidden.reference, hidden.truth, {}, params).vehicles.size(), before - 1);
  }
}

TEST(LidarComparison, ARowIsTheClusterItsBoxOverlapsEvenWhereItsCentroidIsMetresAway) {
  // A long truck: the run measured only its rear, whose centroid is 4 m from the whole cluster's.
  LidarReference reference;
  reference.T_world_camera = {SE3(), SE3()};
  LidarTrackSample truck;
  truck.frame = 1, truck.track_id = 7, truck.has_speed = true, truck.speed_mps = 0.1;
  truck.centroid_camera = Vec3(3.0, 0.5, 12.0);
  truck.box = cv::Rect(700, 0, 500, 375);
  LidarTrackSample car = truck;
  car.track_id = 8, car.centroid_camera = Vec3(-1.0, 0.5, 9.0), car.box = cv::Rect(400, 150, 120, 90);
  reference.samples = {truck, car};
  RunObjectRow rear{1, 3, true, 2.0, Vec3(2.8, 0.5, 8.5), cv::Rect(720, 0, 480, 375)};
  LidarCheckReport r = CompareWithLidar(reference, reference.T_world_camera, {rear}, LidarCheckParams{});
  EXPECT_EQ(r.moving_rows_without_cluster, 0);
  EXPECT_EQ(r.moving_rows_on_standing, 1) << "the truck stands: a moving row there is counted";
  // Without its box the row is 3.5 m from the truck's centroid and 3.8 m from the car's: at no cluster.
  rear.box.reset();
  r = CompareWithLidar(reference, reference.T_world_camera, {rear}, LidarCheckParams{});
  EXPECT_EQ(r.moving_rows_without_cluster, 1);
  // Creeping (0.4 m/s, under the 0.5 m/s a run may report moving from) is not standing.
  reference.samples[0].speed_mps = 0.4;
  rear.box = cv::Rect(720, 0, 480, 375);
  EXPECT_EQ(CompareWithLidar(reference, reference.T_world_camera, {rear}, LidarCheckParams{}).moving_rows_on_standing, 0);
}

TEST(LidarComparison, TheReferencesOwnNoiseIsWhereItsScanPairsDisagree) {
  LidarReference reference;
  for (int k = 0; k < 5; ++k) reference.T_world_camera.push_back(SE3(Mat3::Identity(), Vec3(0.0, 0.0, 0.1 * k)));
  reference.ego_step_disagreement_m = {0.0, 0.01, 0.04, 0.02, 0.03};
  const LidarReferenceNoise noise = ReferenceNoise(reference);
  EXPECT_NEAR(noise.median_step_m, 0.03, 1e-12);  // the upper median of the four pairs
  EXPECT_NEAR(noise.summed_pct_of_path, 25.0, 1e-9);  // 0.10 m over 0.4 m
  // On the synthetic drive the two directions agree to millimetres.
  const LidarReferenceNoise drive = ReferenceNoise(DriveDownTheStreet().reference);
  EXPECT_LT(drive.median_step_m, 0.005);
  EXPECT_EQ(ReferenceNoise(LidarReference{}).summed_pct_of_path, 0.0);
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
                    s.centroid_camera + Vec3(0.3, 0.0, -0.5), std::nullopt});
  }
  rows.push_back({8, 3, true, 3.0, Vec3(0.0, -1.0, 30.0), std::nullopt});  // a "moving object" where there is no cluster
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
