#include "simulation/scenarios.h"

#include <gtest/gtest.h>

#include <cmath>

namespace dslam {
namespace {

TEST(Scenarios, DeterministicForASeedAndDifferentAcrossSeeds) {
  ScenarioOptions opt;
  opt.num_frames = 20;
  const Sequence a = MakeScenario("paper", opt), b = MakeScenario("paper", opt);
  opt.seed = 2;
  const Sequence c = MakeScenario("paper", opt);
  ASSERT_EQ(a.frames.size(), 20u);
  EXPECT_EQ(a.frames[5].objects[0].points[3].p_camera, b.frames[5].objects[0].points[3].p_camera);
  EXPECT_NE(a.frames[5].objects[0].points[3].p_camera, c.frames[5].objects[0].points[3].p_camera);
}

TEST(Scenarios, WorldIsTheFirstCameraFrame) {
  for (const auto& name : ScenarioNames()) {
    ScenarioOptions opt;
    opt.num_frames = 10;
    const Sequence seq = MakeScenario(name, opt);
    EXPECT_TRUE(seq.gt.T_world_camera.front().isApprox(SE3::Identity(), 1e-12)) << name;
  }
}

TEST(Scenarios, PaperObjectHasAConstantPoseChangeAndNoStaticStructure) {
  const Sequence seq = MakeScenario("paper", ScenarioOptions{});
  EXPECT_EQ(seq.frames.size(), 100u);
  ASSERT_EQ(seq.gt.objects.size(), 1u);
  const auto& L = seq.gt.objects.begin()->second.L_world_object;
  const SE3 H1 = L.at(1) * L.at(0).inverse();
  for (int k = 2; k < 100; ++k) EXPECT_TRUE((L.at(k) * L.at(k - 1).inverse()).isApprox(H1, 1e-9)) << k;
  for (const auto& f : seq.frames) {
    EXPECT_TRUE(f.static_points.empty());
    ASSERT_EQ(f.objects.size(), 1u);  // always in view
    EXPECT_GT(f.objects[0].points.size(), 50u);
  }
}

TEST(Scenarios, MeasurementNoiseMatchesSigma) {
  ScenarioOptions opt;
  opt.num_frames = 30;
  opt.noise.point_sigma_m = 0.04;
  const Sequence seq = MakeScenario("city", opt);
  double sum_sq = 0.0;
  int n = 0;
  for (const auto& f : seq.frames)
    for (const auto& p : f.static_points) {
      const Vec3 truth = seq.gt.T_world_camera[f.frame_index].inverse() * seq.gt.static_points_world.at(p.track_id);
      sum_sq += (p.p_camera - truth).squaredNorm();
      n += 3;
    }
  ASSERT_GT(n, 1000);
  EXPECT_NEAR(std::sqrt(sum_sq / n), 0.04, 0.004);
}

TEST(Scenarios, OdometryNoiseIsFivePercentOfTheStep) {
  const Sequence seq = MakeScenario("paper", ScenarioOptions{});
  double sum_sq = 0.0, sum_step = 0.0;
  int n = 0;
  for (const auto& f : seq.frames) {
    if (!f.odometry) continue;
    const SE3 truth = seq.gt.T_world_camera[f.frame_index - 1].inverse() * seq.gt.T_world_camera[f.frame_index];
    EXPECT_NEAR(f.odometry->sigma[0], 0.05 * truth.translation().norm(), 1e-9);
    EXPECT_NEAR(f.odometry->sigma[3], 0.10 * truth.angle(), 1e-9);
    sum_sq += (truth.inverse() * f.odometry->T_prev_curr).Log().head<3>().squaredNorm();
    sum_step += truth.translation().norm();
    n += 3;
  }
  const double mean_step = sum_step / (n / 3);
  EXPECT_NEAR(std::sqrt(sum_sq / n), 0.05 * mean_step, 0.015 * mean_step);
}

TEST(Scenarios, CityHasTheScriptedBehaviours) {
  const Sequence seq = MakeScenario("city", ScenarioOptions{});
  ASSERT_EQ(seq.frames.size(), 200u);
  const auto& gt = seq.gt.objects;
  auto speed = [&](int id, int k) {
    const auto& o = gt.at(id);
    const Vec3 c0 = o.centroid_world.at(k - 1), c1 = o.centroid_world.at(k);
    return (c1 - c0).norm() * seq.frame_rate_hz;
  };
  EXPECT_GT(speed(kCityAccelerating, 60), speed(kCityAccelerating, 10) + 2.0);
  EXPECT_LT(speed(kCityBraking, 50), speed(kCityBraking, 5) - 4.0);
  EXPECT_GT(speed(kCityStopping, 30), 5.0);
  EXPECT_NEAR(speed(kCityStopping, 80), 0.0, 1e-9);
  const auto& turner = gt.at(kCityTurning).L_world_object;
  EXPECT_GT((turner.at(0).inverse() * turner.at(60)).angle(), 1.4);  // about 90 degrees
  // The hidden car: seen, not seen for the occlusion, seen again, with the same id.
  const auto& hidden = gt.at(kCityOccluded).observed_frames;
  EXPECT_TRUE(hidden.count(kCityOcclusionBegin - 1));
  for (int k = kCityOcclusionBegin; k < kCityOcclusionEnd; ++k) EXPECT_FALSE(hidden.count(k));
  EXPECT_TRUE(hidden.count(kCityOcclusionEnd));
  // The stopping car is still observed for a while after it stopped.
  int parked_observed = 0;
  for (int k : gt.at(kCityStopping).observed_frames) parked_observed += k >= 61 && speed(kCityStopping, k) == 0.0;
  EXPECT_GE(parked_observed, 10);
  // Parked cars line the street.
  EXPECT_GE(std::count_if(gt.begin(), gt.end(), [](const auto& o) { return o.first >= kCityParkedIdBase; }), 10);
}

TEST(Scenarios, CrossingHasTheScriptedBehaviours) {
  const Sequence seq = MakeScenario("crossing", ScenarioOptions{});
  ASSERT_EQ(seq.frames.size(), 200u);
  const auto& gt = seq.gt.objects;
  auto speed_kmh = [&](int id, int k) {
    const auto& o = gt.at(id);
    return (o.centroid_world.at(k) - o.centroid_world.at(k - 1)).norm() * seq.frame_rate_hz * 3.6;
  };
  auto camera_speed = [&](int k) {
    return (seq.gt.T_world_camera[k].translation() - seq.gt.T_world_camera[k - 1].translation()).norm() * 10.0;
  };
  EXPECT_NEAR(camera_speed(20), 1.5, 1e-6);  // creeping
  EXPECT_NEAR(camera_speed(70), 0.0, 1e-9);  // waiting at the junction
  // Four cars cross at 30 to 60 km/h, across the camera's axis, and are seen 8 to 25 m away.
  for (int id = kCrossingFirstCrossingId; id < kCrossingFirstCrossingId + 4; ++id) {
    const auto& o = gt.at(id);
    ASSERT_GE(o.observed_frames.size(), 8u) << id;
    const int k = *std::next(o.observed_frames.begin(), static_cast<long>(o.observed_frames.size() / 2));
    EXPECT_GE(speed_kmh(id, k), 29.9) << id;
    EXPECT_LE(speed_kmh(id, k), 60.1) << id;
    const Vec3 dir = o.centroid_world.at(k) - o.centroid_world.at(k - 1);
    EXPECT_GT(std::abs(dir.x()), 10.0 * std::abs(dir.z())) << id;  // crossing
    const double distance = (seq.gt.T_world_camera[k].inverse() * o.centroid_world.at(k)).norm();
    EXPECT_GT(distance, 8.0) << id;
    EXPECT_LT(distance, 25.0) << id;
  }
  for (int id = kCrossingFirstOncomingId; id < kCrossingFirstOncomingId + 2; ++id) {
    const auto& o = gt.at(id);
    ASSERT_GE(o.observed_frames.size(), 8u) << id;
    const int k = *o.observed_frames.rbegin();
    EXPECT_LT((o.centroid_world.at(k) - o.centroid_world.at(k - 1)).z(), -0.9) << id;  // towards the camera
  }
  // The car ahead: moving, stopped, moving again.
  EXPECT_NEAR(speed_kmh(kCrossingStopAndGoId, 10), 14.4, 0.1);
  EXPECT_NEAR(speed_kmh(kCrossingStopAndGoId, 60), 0.0, 1e-9);
  EXPECT_GT(speed_kmh(kCrossingStopAndGoId, 150), 20.0);
  EXPECT_GE(std::count_if(gt.begin(), gt.end(), [](const auto& o) { return o.first >= kCrossingParkedIdBase; }), 2);
}

TEST(Scenarios, CityRepeatsExactlyEveryCycle) {
  ScenarioOptions opt;
  opt.num_frames = 2 * kCityCycleFrames;
  const Sequence seq = MakeScenario("city", opt);
  for (int k : {1, 60, 100, 250}) {
    const auto& a = seq.frames[k];
    const auto& b = seq.frames[k + kCityCycleFrames];
    EXPECT_EQ(a.static_points.size(), b.static_points.size()) << k;
    ASSERT_EQ(a.objects.size(), b.objects.size()) << k;
    for (size_t j = 0; j < a.objects.size(); ++j) EXPECT_EQ(a.objects[j].points.size(), b.objects[j].points.size());
    const SE3 da = seq.gt.T_world_camera[k - 1].inverse() * seq.gt.T_world_camera[k];
    const SE3 db = seq.gt.T_world_camera[k - 1 + kCityCycleFrames].inverse() * seq.gt.T_world_camera[k + kCityCycleFrames];
    EXPECT_TRUE(da.isApprox(db, 1e-6)) << k;
  }
  // A cycle's moving cars are gone before the next cycle starts.
  for (const auto& obj : seq.frames[kCityCycleFrames - 1].objects) EXPECT_GE(obj.object_id, kCityParkedIdBase);
}

TEST(Scenarios, LongCityRunRepeatsItsCarsWithNewIds) {
  ScenarioOptions opt;
  opt.num_frames = 2 * kCityCycleFrames + 50;
  const Sequence seq = MakeScenario("city", opt);
  EXPECT_TRUE(seq.gt.objects.count(10 + kCityBraking));
  EXPECT_TRUE(seq.gt.objects.count(20 + kCityTurning));
  EXPECT_FALSE(seq.gt.objects.at(10 + kCityBraking).observed_frames.empty());
}

TEST(Scenarios, ALongCityStoresItsParkedCarsOnlyWhereTheCameraPasses) {
  // A world that stored every parked car's pose for every frame grew with the square of the length.
  ScenarioOptions opt;
  opt.num_frames = 3 * kCityCycleFrames;
  const Sequence seq = MakeScenario("city", opt);
  size_t parked_poses = 0;
  int parked = 0;
  for (const auto& [id, obj] : seq.gt.objects) {
    if (id < kCityParkedIdBase) continue;
    ++parked;
    parked_poses += obj.L_world_object.size();
    ASSERT_FALSE(obj.L_world_object.empty()) << id;
    // Every frame it was seen in is one it exists in, and it exists for far fewer frames than the run.
    for (int k : obj.observed_frames) EXPECT_TRUE(obj.L_world_object.count(k)) << id << " " << k;
    EXPECT_LT(obj.L_world_object.size(), static_cast<size_t>(kCityCycleFrames)) << id;
  }
  ASSERT_GT(parked, 20);
  EXPECT_LT(parked_poses, static_cast<size_t>(parked) * kCityCycleFrames);
}

// A long run takes the scenario a frame at a time: the same frames as all at once, and the ground
// truth of which frames saw each object only as far as the frames made.
TEST(Scenarios, FrameByFrameEqualsAllAtOnceAndObservationsGrowWithTheFramesMade) {
  ScenarioOptions opt;
  opt.num_frames = 40;
  const Sequence whole = MakeScenario("city", opt);
  SensorSimulator simulator = MakeScenarioSimulator("city", opt);
  EXPECT_EQ(simulator.numFrames(), 40);
  EXPECT_EQ(simulator.groundTruth().T_world_camera.size(), 40u);
  for (const auto& [id, obj] : simulator.groundTruth().objects) EXPECT_TRUE(obj.observed_frames.empty()) << id;
  for (int k = 0; k < 40; ++k) {
    const FrameMeasurement frame = simulator.next();
    const FrameMeasurement& expected = whole.frames[k];
    ASSERT_EQ(frame.frame_index, k);
    ASSERT_EQ(frame.static_points.size(), expected.static_points.size()) << k;
    ASSERT_EQ(frame.objects.size(), expected.objects.size()) << k;
    for (size_t j = 0; j < frame.objects.size(); ++j) {
      ASSERT_EQ(frame.objects[j].points.size(), expected.objects[j].points.size());
      EXPECT_EQ(frame.objects[j].points.back().p_camera, expected.objects[j].points.back().p_camera);
      const auto& observed = simulator.groundTruth().objects.at(frame.objects[j].object_id).observed_frames;
      EXPECT_EQ(*observed.rbegin(), k);
    }
    if (k > 0) {
      EXPECT_EQ(frame.odometry->T_prev_curr.translation(), expected.odometry->T_prev_curr.translation());
    }
  }
  EXPECT_TRUE(simulator.done());
  EXPECT_THROW(simulator.next(), std::logic_error);
  for (const auto& [id, obj] : whole.gt.objects)
    EXPECT_EQ(simulator.groundTruth().objects.at(id).observed_frames, obj.observed_frames) << id;
}

TEST(Scenarios, BadOptionsAreErrors) {
  EXPECT_THROW(MakeScenario("highway", ScenarioOptions{}), std::invalid_argument);
  ScenarioOptions opt;
  opt.noise.point_sigma_m = -1.0;
  EXPECT_THROW(MakeScenario("paper", opt), std::invalid_argument);
  opt = ScenarioOptions{};
  opt.num_frames = 1;
  EXPECT_THROW(MakeScenario("paper", opt), std::invalid_argument);
  // Up front, not a bare std::bad_alloc after a while.
  opt.num_frames = 2'000'000'000;
  try {
    MakeScenario("city", opt);
    ADD_FAILURE() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("at most 100000"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace dslam
