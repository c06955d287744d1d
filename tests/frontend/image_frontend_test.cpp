#include "frontend/image_frontend.h"

#include <gtest/gtest.h>

#include <iostream>
#include <set>

#include "support/synthetic_images.h"

namespace dslam {
namespace {

// A camera sliding right (+x) past a textured wall 10 m away, with a textured box face 6 m away that
// moves right faster than the camera: whole-pixel image motions so the masks stay exact.
constexpr double kFx = 300.0, kWallZ = 10.0, kBoxZ = 6.0;
constexpr double kCameraStepM = 0.2;  // per frame: the wall moves 6 px left in the image
constexpr double kBoxStepM = 0.3;     // per frame: the box moves (0.3 - 0.2) * 300 / 6 = 5 px right
constexpr int kWidth = 320, kHeight = 200;

PinholeCamera Camera() {
  PinholeCamera c;
  c.fx = c.fy = kFx, c.cx = kWidth / 2.0, c.cy = kHeight / 2.0, c.width = kWidth, c.height = kHeight;
  return c;
}

// `box_jump_px`: the box drawn this much farther right than its steady motion puts it.
ImageFrame MakeFrame(int k, int mask_label = 1, int box_jump_px = 0) {
  static const cv::Mat wall = test::RandomTexture(kWidth + 200, kHeight, 21);
  static const cv::Mat box = test::RandomTexture(90, 70, 22);
  ImageFrame f;
  f.frame_index = k;
  f.t_ns = k * 100'000'000LL;
  const int wall_shift = static_cast<int>(std::lround(k * kFx * kCameraStepM / kWallZ));
  cv::Mat image = wall(cv::Rect(wall_shift, 0, kWidth, kHeight)).clone();
  f.depth_m = cv::Mat(kHeight, kWidth, CV_32FC1, cv::Scalar(kWallZ));
  f.instance_ids = cv::Mat(kHeight, kWidth, CV_16UC1, cv::Scalar(0));
  const int box_u = 60 + box_jump_px + static_cast<int>(std::lround(k * kFx * (kBoxStepM - kCameraStepM) / kBoxZ));
  const cv::Rect r(box_u, 70, box.cols, box.rows);
  box.copyTo(image(r));
  f.depth_m(r).setTo(kBoxZ);
  f.instance_ids(r).setTo(mask_label);
  cv::cvtColor(image, f.image, cv::COLOR_GRAY2BGR);
  return f;
}

FrontendParams Params() {
  FrontendParams p;
  p.static_grid.cell_px = 20;
  p.min_mask_area_pct = 1.0;
  p.object_ransac.inlier_threshold_m = 0.05;  // exact depth: a point moving with the wall is an outlier
  return p;
}

TEST(ImageFrontend, TracksTheWallAndTheMovingBoxWithTheirTrueMotions) {
  ImageFrontend frontend(Params(), Camera());
  FrameMeasurement prev = frontend.process(MakeFrame(0));
  EXPECT_FALSE(prev.camera_motion_guess);
  ASSERT_GT(prev.static_points.size(), 60u);
  ASSERT_EQ(prev.objects.size(), 1u);
  EXPECT_EQ(prev.objects[0].object_id, 1);
  for (int k = 1; k <= 5; ++k) {
    const FrameMeasurement curr = frontend.process(MakeFrame(k));
    ASSERT_TRUE(curr.camera_motion_guess) << k;
    EXPECT_NEAR(curr.camera_motion_guess->translation().x(), kCameraStepM, 0.01) << k;
    EXPECT_LT(curr.camera_motion_guess->translation().tail<2>().norm(), 0.01) << k;
    EXPECT_GT(frontend.lastStats().pnp_inliers, 50) << k;
    EXPECT_LT(frontend.lastStats().median_fb_error_px, 0.1) << k;

    // Static tracks continue with their ids; none lies on the box.
    std::map<int64_t, Vec3> before;
    for (const auto& p : prev.static_points) before[p.track_id] = p.p_camera;
    int continued = 0;
    for (const auto& p : curr.static_points) {
      EXPECT_NEAR(p.p_camera.z(), kWallZ, 1e-3);
      if (before.count(p.track_id)) ++continued;
    }
    EXPECT_GT(continued, 0.8 * before.size()) << k;

    // The box's points keep their ids and move by (box - camera) in the camera frame.
    ASSERT_EQ(curr.objects.size(), 1u);
    std::map<int64_t, Vec3> box_before;
    for (const auto& p : prev.objects[0].points) box_before[p.track_id] = p.p_camera;
    int box_continued = 0;
    double sum_dx = 0.0;
    for (const auto& p : curr.objects[0].points) {
      EXPECT_NEAR(p.p_camera.z(), kBoxZ, 1e-3);
      const auto b = box_before.find(p.track_id);
      if (b == box_before.end()) continue;
      ++box_continued;
      // Within a pixel (2 cm at 6 m): near the box's edge the flow window also sees the wall.
      EXPECT_NEAR((p.p_camera - b->second).x(), kBoxStepM - kCameraStepM, 0.02);
      sum_dx += (p.p_camera - b->second).x();
    }
    ASSERT_GE(box_continued, 20) << k;
    // The tracks it could continue are the previous measurement's; those that did, its tracked count.
    const FrontendFrameStats::ObjectCounts& counts = frontend.lastStats().object_counts.at(1);
    EXPECT_EQ(counts.previous, static_cast<int>(prev.objects[0].points.size())) << k;
    EXPECT_EQ(counts.tracked, box_continued) << k;
    EXPECT_NEAR(sum_dx / box_continued, kBoxStepM - kCameraStepM, 0.003) << k;
    // Its motion fit goes downstream with it: the box's own step, camera motion removed, over the
    // tracks that carried on.
    ASSERT_TRUE(curr.objects[0].motion_fit) << k;
    const ObjectMotionFit& fit = *curr.objects[0].motion_fit;
    EXPECT_EQ(fit.num_inliers, box_continued) << k;
    EXPECT_NEAR(fit.H_camera_prev.translation().x(), kBoxStepM, 0.01) << k;
    EXPECT_LT(fit.H_camera_prev.angle(), 0.01) << k;
    EXPECT_NEAR(fit.centroid_camera_prev.z(), kBoxZ, 1e-3) << k;
    prev = curr;
  }
}

TEST(ImageFrontend, AFitItRejectedDoesNotWidenTheAccelerationGateForTheNext) {
  // The box moves steadily, then jumps 8 px (0.16 m at 6 m: 16 m/s^2, over a bound of 10) at frames 6 and
  // 7, and moves steadily from there: the tracks of frames 6 and 7 are wrong in one direction, as a
  // half-hidden car's tracks stuck to the edge of what hides it. Both fits are rejected, and the steady
  // motion after them is accepted. (A gate whose bound grew with each frame since the motion it holds let
  // the second wrong fit through, then held it and rejected the right motion after it.)
  FrontendParams params = Params();
  params.object_max_acceleration_mps2 = 10.0;  // 0.1 m a frame: jumps the flow follows can break it
  ImageFrontend frontend(params, Camera());
  const auto jump = [](int k) { return 8 * (k >= 6) + 8 * (k >= 7); };
  std::map<int, bool> rejected;
  std::map<int, double> step_m;
  for (int k = 0; k <= 9; ++k) {
    const FrameMeasurement m = frontend.process(MakeFrame(k, 1, jump(k)));
    const auto counts = frontend.lastStats().object_counts.find(1);
    ASSERT_NE(counts, frontend.lastStats().object_counts.end()) << k;
    rejected[k] = counts->second.motion_rejected;
    for (const auto& o : m.objects)
      if (o.motion_fit) step_m[k] = o.motion_fit->H_camera_prev.translation().x();
  }
  for (int k = 1; k <= 5; ++k) EXPECT_FALSE(rejected[k]) << k;
  EXPECT_TRUE(rejected[6]);
  EXPECT_TRUE(rejected[7]);
  EXPECT_FALSE(rejected[8]);
  ASSERT_TRUE(step_m.count(8));
  EXPECT_NEAR(step_m[8], kBoxStepM, 0.01);
}

TEST(ImageFrontend, OdometryThatContradictsThePnpMotionIsDroppedAndCounted) {
  ImageFrontend frontend(Params(), Camera());
  frontend.process(MakeFrame(0));
  const SE3 step(Eigen::Quaterniond::Identity(), Vec3(kCameraStepM, 0.0, 0.0));
  // Right odometry (within its sigmas): fused, handed on.
  ImageFrame good = MakeFrame(1);
  good.odometry = OdometryMeasurement{step * SE3::Exp((Vec6() << 0.01, 0.0, 0.0, 0.0, 0.0, 0.0).finished()),
                                      (Vec6() << 0.03, 0.03, 0.03, 0.005, 0.005, 0.005).finished()};
  const FrameMeasurement a = frontend.process(good);
  EXPECT_FALSE(frontend.lastStats().odometry_rejected);
  ASSERT_TRUE(a.odometry);
  // A corrupt record, 60 m forward: dropped for this frame; the camera motion comes from PnP alone.
  ImageFrame bad = MakeFrame(2);
  bad.odometry = OdometryMeasurement{SE3(Eigen::Quaterniond::Identity(), Vec3(kCameraStepM, 0.0, 60.0)),
                                     (Vec6() << 0.03, 0.03, 0.03, 0.005, 0.005, 0.005).finished()};
  const FrameMeasurement b = frontend.process(bad);
  EXPECT_TRUE(frontend.lastStats().odometry_rejected);
  EXPECT_FALSE(b.odometry);
  ASSERT_TRUE(b.camera_motion_guess);
  EXPECT_LT((b.camera_motion_guess->translation() - step.translation()).norm(), 0.01);
  // The gate is a setting.
  FrontendParams params = Params();
  params.odometry_gate_chi2 = 0.0;
  EXPECT_THROW(ImageFrontend(params, Camera()), std::invalid_argument);
}

// After dropped frames (serve composes their odometry into the next frame's), the flow spans several frames'
// motion, where look-alikes can give a well-supported but wrong PnP: odometry that PnP contradicts is kept
// there, with the static points that agree with it. Without a gap the same contradiction drops the odometry.
TEST(ImageFrontend, AfterAGapOdometryThatPnpContradictsIsKept) {
  const Vec6 sigma = (Vec6() << 0.03, 0.03, 0.03, 0.005, 0.005, 0.005).finished();
  // 0.3 m along the optical axis off the true motion: 10 sigma.
  auto odometry = [&](int steps) {
    return OdometryMeasurement{SE3(Eigen::Quaterniond::Identity(), Vec3(steps * kCameraStepM, 0.0, 0.3)), sigma};
  };
  ImageFrontend steady(Params(), Camera());
  steady.process(MakeFrame(0));
  steady.process(MakeFrame(1));
  ImageFrame next = MakeFrame(2);
  next.odometry = odometry(1);
  const FrameMeasurement without_gap = steady.process(next);
  EXPECT_TRUE(steady.lastStats().odometry_rejected);
  EXPECT_FALSE(without_gap.odometry);

  ImageFrontend gapped(Params(), Camera());
  gapped.process(MakeFrame(0));
  gapped.process(MakeFrame(1));
  ImageFrame after = MakeFrame(3);  // frame 2 dropped: 0.2 s since frame 1
  after.frame_index = 2;            // the front-end's own count goes on
  after.odometry = odometry(2);
  const FrameMeasurement with_gap = gapped.process(after);
  EXPECT_FALSE(gapped.lastStats().odometry_rejected);
  ASSERT_TRUE(with_gap.odometry);
  ASSERT_TRUE(with_gap.camera_motion_guess);
  EXPECT_LT((with_gap.camera_motion_guess->translation() - after.odometry->T_prev_curr.translation()).norm(), 1e-9);
  EXPECT_GT(with_gap.static_points.size(), 0u);
}

// When PnP finds no consensus across a gap (dropped frames: the flow's matches are mostly look-alikes) and
// there is odometry, the odometry is the camera's motion and no unverified static track goes on to the
// back-end: handed on, 28 look-alikes held a rendered city's camera 10 m behind its odometry after 18
// dropped frames. Without a gap, or without odometry, they go on as before.
TEST(ImageFrontend, WithoutAPnpConsensusAcrossAGapNoStaticTrackGoesOnBesideTheOdometry) {
  FrontendParams params = Params();
  params.pnp.min_inliers = 100000;  // PnP never reaches a consensus here
  const Vec6 sigma = (Vec6() << 0.03, 0.03, 0.03, 0.005, 0.005, 0.005).finished();
  auto static_tracked = [&](bool gap, bool with_odometry) {
    ImageFrontend frontend(params, Camera());
    frontend.process(MakeFrame(0));
    const int steps = gap ? 2 : 1;
    ImageFrame next = MakeFrame(steps);  // with a gap, frame 1 was dropped
    next.frame_index = 1;
    if (with_odometry)
      next.odometry =
          OdometryMeasurement{SE3(Eigen::Quaterniond::Identity(), Vec3(steps * kCameraStepM, 0.0, 0.0)), sigma};
    const FrameMeasurement m = frontend.process(next);
    EXPECT_FALSE(frontend.lastStats().camera_from_pnp);
    EXPECT_EQ(m.odometry.has_value(), with_odometry);
    return frontend.lastStats().static_tracked;
  };
  EXPECT_EQ(static_tracked(true, true), 0);
  EXPECT_GT(static_tracked(true, false), 50);
  EXPECT_GT(static_tracked(false, true), 50);
}

TEST(ImageFrontend, FollowsTheBoxWhenTheSegmenterRelabelsItEveryFrame) {
  FrontendParams params = Params();
  params.association.mask_ids_tracked = false;
  ImageFrontend frontend(params, Camera());
  const int id = frontend.process(MakeFrame(0, 7)).objects.at(0).object_id;
  for (int k = 1; k <= 3; ++k) {
    const FrameMeasurement m = frontend.process(MakeFrame(k, 7 + 10 * k));
    ASSERT_EQ(m.objects.size(), 1u);
    EXPECT_EQ(m.objects[0].object_id, id) << k;
  }
}

TEST(ImageFrontend, RejectsBadFramesAndCarriesOnFromTheLastGoodOne) {
  ImageFrontend frontend(Params(), Camera());
  frontend.process(MakeFrame(0));

  ImageFrame wrong_size = MakeFrame(1);
  cv::resize(wrong_size.image, wrong_size.image, {160, 100});
  try {
    frontend.process(wrong_size);
    FAIL() << "accepted an image of the wrong size";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("depth is 320x200 but the image is 160x100"), std::string::npos) << e.what();
  }
  ImageFrame bad_depth = MakeFrame(1);
  bad_depth.depth_m.convertTo(bad_depth.depth_m, CV_16U);
  EXPECT_THROW(frontend.process(bad_depth), std::invalid_argument);
  ImageFrame bad_mask = MakeFrame(1);
  bad_mask.instance_ids = cv::Mat(10, 10, CV_16UC1, cv::Scalar(0));
  EXPECT_THROW(frontend.process(bad_mask), std::invalid_argument);
  ImageFrame nan_odometry = MakeFrame(1);
  nan_odometry.odometry = OdometryMeasurement{};
  nan_odometry.odometry->sigma[2] = std::nan("");
  EXPECT_THROW(frontend.process(nan_odometry), std::invalid_argument);

  const FrameMeasurement good = frontend.process(MakeFrame(1));
  EXPECT_GT(frontend.lastStats().static_tracked, 50);  // tracks from frame 0 survived the rejected frames
  ASSERT_TRUE(good.camera_motion_guess);
  EXPECT_NEAR(good.camera_motion_guess->translation().x(), kCameraStepM, 0.01);
  try {
    frontend.process(MakeFrame(1));
    FAIL() << "accepted a repeated frame";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("increasing order"), std::string::npos) << e.what();
  }
}

void ExpectSameMeasurement(const FrameMeasurement& a, const FrameMeasurement& b) {
  EXPECT_EQ(a.frame_index, b.frame_index);
  ASSERT_EQ(a.static_points.size(), b.static_points.size()) << a.frame_index;
  for (size_t i = 0; i < a.static_points.size(); ++i) {
    EXPECT_EQ(a.static_points[i].track_id, b.static_points[i].track_id);
    EXPECT_EQ(a.static_points[i].p_camera, b.static_points[i].p_camera);
  }
  ASSERT_EQ(a.objects.size(), b.objects.size()) << a.frame_index;
  for (size_t o = 0; o < a.objects.size(); ++o) {
    EXPECT_EQ(a.objects[o].object_id, b.objects[o].object_id);
    ASSERT_EQ(a.objects[o].points.size(), b.objects[o].points.size()) << a.frame_index;
    for (size_t i = 0; i < a.objects[o].points.size(); ++i) {
      EXPECT_EQ(a.objects[o].points[i].track_id, b.objects[o].points[i].track_id);
      EXPECT_EQ(a.objects[o].points[i].p_camera, b.objects[o].points[i].p_camera);
    }
    ASSERT_EQ(a.objects[o].motion_fit.has_value(), b.objects[o].motion_fit.has_value());
    if (a.objects[o].motion_fit) {
      EXPECT_EQ(a.objects[o].motion_fit->H_camera_prev.translation(), b.objects[o].motion_fit->H_camera_prev.translation());
    }
  }
  ASSERT_EQ(a.camera_motion_guess.has_value(), b.camera_motion_guess.has_value());
  if (a.camera_motion_guess) {
    EXPECT_EQ(a.camera_motion_guess->translation(), b.camera_motion_guess->translation());
  }
}

// For a pipeline whose back-end refuses a frame the front-end took (VehiclePipeline): after undoLast() the
// front-end is as it was before that frame, down to its track ids, object ids and object-motion memory.
TEST(ImageFrontend, UndoLastTakesAFrameBackAsIfItNeverCame) {
  ImageFrontend straight(Params(), Camera()), undoing(Params(), Camera());
  EXPECT_THROW(undoing.undoLast(), std::logic_error);  // nothing yet
  for (int k = 0; k < 8; ++k) {
    if (k == 4) {
      // A frame whose box the segmenter labels anew: a new object id, new tracks, a new motion memory.
      undoing.process(MakeFrame(k, 9));
      undoing.undoLast();
      EXPECT_THROW(undoing.undoLast(), std::logic_error);  // once
    }
    const FrameMeasurement a = straight.process(MakeFrame(k));
    const FrameMeasurement b = undoing.process(MakeFrame(k));
    ExpectSameMeasurement(a, b);
    EXPECT_EQ(straight.lastStats().static_tracked, undoing.lastStats().static_tracked);
  }
}

// Signed instance ids (Mask R-CNN's -1 for "none") are background where negative: the same measurements as
// unsigned ids with 0 there.
TEST(ImageFrontend, NegativeSignedInstanceIdsAreBackgroundAsUnsignedZerosAre) {
  ImageFrontend unsigned_ids(Params(), Camera()), signed_ids(Params(), Camera());
  for (int k = 0; k < 4; ++k) {
    const ImageFrame frame = MakeFrame(k);
    ImageFrame with_none = frame;
    frame.instance_ids.convertTo(with_none.instance_ids, CV_32S);
    with_none.instance_ids.setTo(-1, frame.instance_ids == 0);
    ASSERT_GT(cv::countNonZero(with_none.instance_ids < 0), 0);
    const FrameMeasurement a = unsigned_ids.process(frame);
    const FrameMeasurement b = signed_ids.process(with_none);
    ExpectSameMeasurement(a, b);
    EXPECT_EQ(a.objects.size(), 1u) << k;
    EXPECT_EQ(unsigned_ids.lastStats().mask_labels, signed_ids.lastStats().mask_labels) << k;
  }
}

// A frame prepared elsewhere (a pipeline's other thread) gives the measurement the front-end gives from the
// frame alone; a frame that cannot be prepared is refused by name.
TEST(ImageFrontend, AFramePreparedElsewhereGivesTheSameMeasurement) {
  ImageFrontend alone(Params(), Camera()), given(Params(), Camera());
  for (int k = 0; k < 6; ++k) {
    const ImageFrame frame = MakeFrame(k);
    const PreparedFrame prepared = ImageFrontend::Prepare(Params(), frame);
    EXPECT_EQ(prepared.label_areas.size(), 1u) << k;
    EXPECT_GT(cv::countNonZero(prepared.background_allowed), 0) << k;
    EXPECT_GT(cv::countNonZero(prepared.near_edge), 0) << k;
    const FrameMeasurement a = alone.process(frame);
    const FrameMeasurement b = given.process(frame, &prepared);
    ExpectSameMeasurement(a, b);
    EXPECT_EQ(alone.lastStats().static_tracked, given.lastStats().static_tracked) << k;
    EXPECT_EQ(alone.lastStats().mask_labels, given.lastStats().mask_labels) << k;
  }
  ImageFrame bad = MakeFrame(6);
  bad.depth_m = cv::Mat(10, 10, CV_32FC1, cv::Scalar(1.0f));
  EXPECT_THROW(ImageFrontend::Prepare(Params(), bad), std::invalid_argument);
}

TEST(ImageFrontend, IgnoresMasksBelowTheAreaThresholdAndObjectsBeyondRange) {
  FrontendParams params = Params();
  params.min_mask_area_pct = 20.0;  // the box covers 6300 / 64000 px, under 20 %
  ImageFrontend small(params, Camera());
  EXPECT_TRUE(small.process(MakeFrame(0)).objects.empty());
  // Under it, the object is measured, with the share of the image its mask covers (the classifier's
  // small_object_area_pct reads it).
  ImageFrontend measured(Params(), Camera());
  const FrameMeasurement box = measured.process(MakeFrame(0));
  ASSERT_EQ(box.objects.size(), 1u);
  ASSERT_TRUE(box.objects[0].mask_area_frac.has_value());
  EXPECT_DOUBLE_EQ(*box.objects[0].mask_area_frac, 6300.0 / 64000.0);
  params = Params();
  params.object_max_distance_m = 5.0;  // the box is 6 m away
  ImageFrontend far(params, Camera());
  const FrameMeasurement m = far.process(MakeFrame(0));
  EXPECT_TRUE(m.objects.empty());
  for (const auto& p : m.static_points) EXPECT_NEAR(p.p_camera.z(), kWallZ, 1e-3);  // no box point became static
}

namespace leaving {
// A still camera before the wall, and a box 6 m away crossing to the right at 15 px a frame: its right
// edge is at 140 + 15 k px, so it leaves the view over frames 12 to 20.
constexpr int kBoxStepPx = 15;

ImageFrame MakeFrame(int k) {
  static const cv::Mat wall = test::RandomTexture(kWidth, kHeight, 31);
  static const cv::Mat box = test::RandomTexture(120, 70, 32);
  ImageFrame f;
  f.frame_index = k;
  f.t_ns = k * 100'000'000LL;
  cv::Mat image = wall.clone();
  f.depth_m = cv::Mat(kHeight, kWidth, CV_32FC1, cv::Scalar(kWallZ));
  f.instance_ids = cv::Mat(kHeight, kWidth, CV_16UC1, cv::Scalar(0));
  const cv::Rect r = cv::Rect(20 + kBoxStepPx * k, 70, box.cols, box.rows) & cv::Rect(0, 0, kWidth, kHeight);
  if (!r.empty()) {
    box(cv::Rect(0, 0, r.width, r.height)).copyTo(image(r));  // its left part, the rest is out of view
    f.depth_m(r).setTo(kBoxZ);
    f.instance_ids(r).setTo(1);
  }
  cv::cvtColor(image, f.image, cv::COLOR_GRAY2BGR);
  return f;
}
}  // namespace leaving

TEST(ImageFrontend, ABoxLeavingTheViewGetsItsNewPointsOnThePartThatStays) {
  FrontendParams params = Params();
  params.max_points_per_object = 30;
  ImageFrontend frontend(params, Camera());
  FrameMeasurement prev = frontend.process(leaving::MakeFrame(0));
  int added = 0, added_leaving = 0;  // new box points once its motion is confirmed; those the next step takes out
  size_t most_points = 0;
  for (int k = 1; k <= 17; ++k) {
    const FrameMeasurement curr = frontend.process(leaving::MakeFrame(k));
    ASSERT_EQ(curr.objects.size(), 1u) << k;
    most_points = std::max(most_points, curr.objects[0].points.size());
    std::set<int64_t> before;
    for (const auto& o : prev.objects)
      for (const auto& p : o.points) before.insert(p.track_id);
    for (const auto& p : curr.objects[0].points) {
      if (k < 4 || before.count(p.track_id)) continue;
      ++added;
      added_leaving += Camera().project(p.p_camera).x() + leaving::kBoxStepPx > kWidth - 1;
    }
    prev = curr;
  }
  std::cout << "new box points " << added << ", " << added_leaving << " of them where the next step takes them out "
            << "of view; at most " << most_points << " points in a frame" << std::endl;
  ASSERT_GT(added, 20);
  EXPECT_EQ(added_leaving, 0);
  // Points that are about to leave do not take the places of those that stay.
  EXPECT_GT(most_points, static_cast<size_t>(params.max_points_per_object));
}

namespace passing {
// A still camera and a car's side coming towards it at a grazing angle: a textured vertical plane at
// x = -1.5 m, 6 m long, whose near end comes 1.2 m closer every frame, in front of a wall 20 m away.
// Between two frames a point of the side at depth z stretches along u by (z / (z - 1.2))^2: 30 % and more
// within about 8.5 m, beyond what Lucas-Kanade's translation model follows.
constexpr double kSideX = -1.5, kSideLength = 6.0, kStepZ = 1.2, kFirstZ = 10.0, kWallZ = 20.0;
constexpr double kTexturePerM = 20.0;  // texture pixels per metre on the side

// Where the ray through pixel (u, v) meets the side at frame k: its depth, and the texture pixel there.
bool OnSide(double u, double v, int k, double* z, cv::Point2f* texture_px) {
  const PinholeCamera cam = Camera();
  const double dx = (u - cam.cx) / cam.fx, dy = (v - cam.cy) / cam.fy, near_z = kFirstZ - kStepZ * k;
  *z = dx < 0.0 ? kSideX / dx : -1.0;
  if (!(*z >= near_z && *z <= near_z + kSideLength && std::abs(*z * dy) <= 1.0)) return false;
  *texture_px = cv::Point2f(static_cast<float>((*z - near_z) * kTexturePerM),
                            static_cast<float>((*z * dy + 1.0) * kTexturePerM));
  return true;
}

ImageFrame MakeFrame(int k) {
  static const cv::Mat side = test::RandomTexture(static_cast<int>(kSideLength * kTexturePerM) + 2, 42, 41);
  static const cv::Mat wall = test::RandomTexture(700, 420, 42);
  // The image is rendered 4 x 4 times finer and averaged down: the side, seen so obliquely, would
  // otherwise alias from frame to frame (as a renderer without mipmaps makes it sparkle).
  constexpr int kSuper = 4;
  cv::Mat map_u(kHeight * kSuper, kWidth * kSuper, CV_32FC1), map_v(map_u.size(), CV_32FC1);
  cv::Mat on_side(map_u.size(), CV_8UC1, cv::Scalar(0));
  for (int v = 0; v < map_u.rows; ++v)
    for (int u = 0; u < map_u.cols; ++u) {
      const double pu = (u + 0.5) / kSuper - 0.5, pv = (v + 0.5) / kSuper - 0.5;
      double z;
      cv::Point2f texture_px;
      if (OnSide(pu, pv, k, &z, &texture_px)) {
        map_u.at<float>(v, u) = texture_px.x, map_v.at<float>(v, u) = texture_px.y;
        on_side.at<uint8_t>(v, u) = 1;
      } else {
        map_u.at<float>(v, u) = static_cast<float>(350.0 + kWallZ * (pu - Camera().cx) / Camera().fx * 15.0);
        map_v.at<float>(v, u) = static_cast<float>(210.0 + kWallZ * (pv - Camera().cy) / Camera().fy * 15.0);
      }
    }
  cv::Mat side_image, fine;
  cv::remap(side, side_image, map_u, map_v, cv::INTER_LINEAR, cv::BORDER_REPLICATE);
  cv::remap(wall, fine, map_u, map_v, cv::INTER_LINEAR, cv::BORDER_REPLICATE);
  side_image.copyTo(fine, on_side);
  cv::Mat grey;
  cv::resize(fine, grey, cv::Size(kWidth, kHeight), 0, 0, cv::INTER_AREA);

  ImageFrame f;
  f.frame_index = k;
  f.t_ns = k * 100'000'000LL;
  cv::cvtColor(grey, f.image, cv::COLOR_GRAY2BGR);
  f.depth_m = cv::Mat(kHeight, kWidth, CV_32FC1, cv::Scalar(kWallZ));
  f.instance_ids = cv::Mat(kHeight, kWidth, CV_16UC1, cv::Scalar(0));
  for (int v = 0; v < kHeight; ++v)
    for (int u = 0; u < kWidth; ++u) {
      double z;
      cv::Point2f texture_px;
      if (!OnSide(u, v, k, &z, &texture_px)) continue;
      f.depth_m.at<float>(v, u) = static_cast<float>(z);
      f.instance_ids.at<uint16_t>(v, u) = 1;
    }
  return f;
}

// Where the side's step takes the point seen at p_camera: its pixel's ray meets the side's plane.
// (Not p_camera itself moved: its depth is that of its pixel's centre, and on so grazing a side the
// depth changes by a tenth of a metre from one pixel to the next.)
Vec2 Stepped(const Vec3& p_camera) {
  const Vec2 px = Camera().project(p_camera);
  const double dx = (px.x() - Camera().cx) / Camera().fx, dy = (px.y() - Camera().cy) / Camera().fy;
  const double z = kSideX / dx;
  return Camera().project(Vec3(kSideX, z * dy, z - kStepZ));
}

struct Run {
  int tracked = 0, reacquired = 0;   // from frame 4 (the near end within 5.2 m), and over all frames
  int continued = 0, within_1px = 0;  // tracks carried over, and those within a pixel of the side's step
  int good_fits = 0;                  // motion fits within 5 cm of the side's step
};

// `odometry_error_m`: each frame comes with an odometry increment this far off sideways (the camera
// stands still), as a noisy wheel odometry gives.
// `max_flow_deformation`: WarpedSearchParams' (the default when not given).
Run Drive(int radius_px, double odometry_error_m = 0.0,
          double max_flow_deformation = WarpedSearchParams{}.max_flow_deformation) {
  FrontendParams params = Params();
  params.min_mask_area_pct = 0.2;
  params.object_ransac.inlier_threshold_m = FrontendParams{}.object_ransac.inlier_threshold_m;
  params.warped_search.radius_px = radius_px;
  params.warped_search.max_flow_deformation = max_flow_deformation;
  ImageFrontend frontend(params, Camera());
  FrameMeasurement prev = frontend.process(MakeFrame(0));
  Run run;
  for (int k = 1; k <= 6; ++k) {
    ImageFrame frame = MakeFrame(k);
    if (odometry_error_m != 0.0) frame.odometry = OdometryMeasurement{SE3(Mat3::Identity(), Vec3(odometry_error_m, 0, 0))};
    const FrameMeasurement curr = frontend.process(frame);
    const auto counts = frontend.lastStats().object_counts.find(1);
    if (counts != frontend.lastStats().object_counts.end()) {
      if (k >= 4) run.tracked += counts->second.tracked;
      run.reacquired += counts->second.reacquired;
    }
    std::map<int64_t, Vec3> before;
    for (const auto& o : prev.objects)
      for (const auto& p : o.points) before[p.track_id] = p.p_camera;
    for (const auto& o : curr.objects) {
      for (const auto& p : o.points) {
        const auto b = before.find(p.track_id);
        if (b == before.end()) continue;
        ++run.continued;
        run.within_1px += (Camera().project(p.p_camera) - Stepped(b->second)).norm() < 1.0;
      }
      if (o.motion_fit && (o.motion_fit->H_camera_prev.translation() - Vec3(0.0, 0.0, -kStepZ)).norm() < 0.05)
        ++run.good_fits;
    }
    prev = curr;
  }
  return run;
}
}  // namespace passing

TEST(ImageFrontend, KeepsTheTracksOfACarsSideThatStretchesAsItPassesClose) {
  const passing::Run with = passing::Drive(WarpedSearchParams{}.radius_px);
  const passing::Run without = passing::Drive(0);
  std::cout << "tracks kept on the near side: " << with.tracked << " with the warped search (" << with.reacquired
            << " found by it), " << without.tracked << " without; within a pixel of the truth: " << with.within_1px
            << " of " << with.continued << " with, " << without.within_1px << " of " << without.continued
            << " without; good motion fits " << with.good_fits << " with, " << without.good_fits << " without"
            << std::endl;
  EXPECT_GT(with.reacquired, 20);
  EXPECT_EQ(without.reacquired, 0);
  EXPECT_GT(with.tracked, without.tracked);
  EXPECT_GT(with.within_1px, 2 * without.within_1px);
  // What it found is more precise than what the flow keeps on so stretched a side, not less.
  EXPECT_GT(static_cast<double>(with.within_1px) / with.continued,
            static_cast<double>(without.within_1px) / without.continued);
  EXPECT_GE(with.good_fits, without.good_fits);
}

// The search starts from where the camera's and the car's motions put each point. With the camera's
// motion from an odometry 0.4 m off (20 to 30 px at the side's 4 to 6 m), it would search in the wrong
// place; the static tracks found first give the camera's true motion.
TEST(ImageFrontend, SearchesTheStretchedSideWhereTheStaticTracksNotTheOdometryPutTheCamera) {
  const passing::Run exact = passing::Drive(WarpedSearchParams{}.radius_px);
  const passing::Run off = passing::Drive(WarpedSearchParams{}.radius_px, 0.4);
  std::cout << "found by the warped search: " << exact.reacquired << " with no odometry, " << off.reacquired
            << " with an odometry 0.4 m off; tracks kept on the near side " << exact.tracked << ", " << off.tracked
            << std::endl;
  EXPECT_GT(off.reacquired, 0.8 * exact.reacquired);
  EXPECT_GT(off.tracked, 0.8 * exact.tracked);
}

// Where the side stretches by 60 % and more, a match the flow found but the warped search did not confirm
// is dropped: Lucas-Kanade's square window cannot follow such a patch, and what it finds there is more
// often a look-alike than the point.
TEST(ImageFrontend, DropsTheFlowsMatchesOnAPatchTooDeformedForItThatTheSearchDoesNotConfirm) {
  const passing::Run dropping = passing::Drive(WarpedSearchParams{}.radius_px);
  const passing::Run keeping = passing::Drive(WarpedSearchParams{}.radius_px, 0.0, 1e9);
  const int wrong_dropping = dropping.continued - dropping.within_1px, wrong_keeping = keeping.continued - keeping.within_1px;
  std::cout << "tracks carried on the near side: " << dropping.continued << " (" << wrong_dropping
            << " more than a pixel off) dropping the unconfirmed flow matches, " << keeping.continued << " ("
            << wrong_keeping << ") keeping them; good motion fits " << dropping.good_fits << ", " << keeping.good_fits
            << std::endl;
  EXPECT_LT(wrong_dropping, 0.75 * wrong_keeping);
  EXPECT_GE(dropping.within_1px, keeping.within_1px - 2);  // it drops what is wrong, not what is right
  EXPECT_GE(dropping.good_fits, keeping.good_fits);
}

}  // namespace
}  // namespace dslam
