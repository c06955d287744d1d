#include "pipeline/reference_objects.h"

#include <gtest/gtest.h>

namespace dslam {
namespace {

// A 100x80 camera; the exact mask has car 7 on the left (u < 40) and car 9 on the right (u >= 60), each
// 40x80 pixels, and a 1x2 speck of object 11 too small to count.
struct Scene {
  PinholeCamera camera;
  cv::Mat ids = cv::Mat(80, 100, CV_16UC1, cv::Scalar(0));
  Scene() {
    camera.fx = camera.fy = 100.0, camera.cx = 50.0, camera.cy = 40.0, camera.width = 100, camera.height = 80;
    ids(cv::Rect(0, 0, 40, 80)).setTo(7);
    ids(cv::Rect(60, 0, 40, 80)).setTo(9);
    ids(cv::Rect(45, 10, 1, 2)).setTo(11);
  }
  // A point at depth 10 m that projects to pixel (u, v).
  Vec3 At(double u, double v) const { return camera.backProject(u, v, 10.0); }
};

ObjectObservation Object(int id, const std::vector<Vec3>& points) {
  ObjectObservation o;
  o.object_id = id;
  for (size_t i = 0; i < points.size(); ++i) o.points.push_back({static_cast<int64_t>(100 * id + i), points[i]});
  return o;
}

TEST(ReferenceObjectMatcher, ARunObjectIsTheReferenceObjectMostOfItsPointsFallIn) {
  const Scene scene;
  ReferenceObjectMatcher matcher(scene.camera, 0.05);
  matcher.keep(3, scene.ids);
  FrameMeasurement m;
  m.frame_index = 3;
  // Run object 1: three of four points on car 7. Run object 2: two on car 9, two on the background (half:
  // enough). Run object 5: one of three points on car 9 (not enough). Run object 6: also on car 7, fewer points.
  m.objects = {Object(1, {scene.At(10, 10), scene.At(20, 40), scene.At(30, 70), scene.At(50, 40)}),
               Object(2, {scene.At(70, 10), scene.At(80, 20), scene.At(50, 50), scene.At(55, 60)}),
               Object(5, {scene.At(90, 10), scene.At(50, 20), scene.At(52, 30)}),
               Object(6, {scene.At(5, 5), scene.At(6, 6)})};
  matcher.match(3, m);
  const auto& ids = matcher.runObjectIds();
  ASSERT_EQ(ids.size(), 2u);
  EXPECT_EQ(ids.at({3, 7}), 1);
  EXPECT_EQ(ids.at({3, 9}), 2);
  EXPECT_TRUE(matcher.visible(3, 7));
  EXPECT_TRUE(matcher.visible(3, 9));
  EXPECT_FALSE(matcher.visible(3, 11));  // 2 pixels of 8000: under 0.05 %
  EXPECT_FALSE(matcher.visible(4, 7));   // no mask kept for frame 4

  // A frame whose mask was not kept matches nothing; a kept mask is used once.
  matcher.match(4, m);
  matcher.match(3, m);
  EXPECT_EQ(matcher.runObjectIds().size(), 2u);
}

}  // namespace
}  // namespace dslam
