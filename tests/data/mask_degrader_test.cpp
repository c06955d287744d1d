// The degraded segmenter of the front-end study: each error happens as often as its parameter says, its
// ids say where they come from, it is reproducible, and its score is that of the masks it made.
#include "data/mask_degrader.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

namespace dslam {
namespace {

constexpr int kObjects = 12;

// kObjects separate squares of 40x40 px (the same every frame), on a 640x480 image.
cv::Mat Squares() {
  cv::Mat ids = cv::Mat::zeros(480, 640, CV_16U);
  for (int i = 0; i < kObjects; ++i) ids(cv::Rect(20 + (i % 6) * 100, 40 + (i / 6) * 200, 40, 40)).setTo(i + 1);
  return ids;
}

MaskDegraderParams Nothing() {
  MaskDegraderParams p;
  p.miss_rate = p.miss_rate_small = p.boundary_frac = p.box_rate = p.split_rate = p.merge_rate = p.id_switch_rate =
      p.untracked_rate = 0.0;
  return p;
}

TEST(MaskDegrader, WithoutErrorsItGivesTheExactMasksBack) {
  MaskDegrader degrader(Nothing());
  const cv::Mat exact = Squares();
  SegmentationScore score;
  for (int k = 0; k < 5; ++k) {
    const DegradedMaskFrame d = degrader.degrade(k, exact);
    cv::Mat exact32;
    exact.convertTo(exact32, CV_32S);
    EXPECT_EQ(cv::countNonZero(d.ids != exact32), 0);
    EXPECT_EQ(d.source_of.size(), static_cast<size_t>(kObjects));
    for (const auto& [id, source] : d.source_of) EXPECT_EQ(id, source);
    score.add(exact, d.ids, 1);
  }
  EXPECT_EQ(score.instances, 5 * kObjects);
  EXPECT_DOUBLE_EQ(score.miou(), 1.0);
  EXPECT_DOUBLE_EQ(score.detectionRate(), 1.0);
}

TEST(MaskDegrader, EachErrorHappensAsOftenAsItsRateSays) {
  constexpr int kFrames = 250;
  const cv::Mat exact = Squares();
  struct Case {
    const char* name;
    double MaskDegraderParams::*rate;
    int DegradedMaskFrame::*count;
  };
  for (const Case& c : {Case{"miss", &MaskDegraderParams::miss_rate, &DegradedMaskFrame::missed},
                        Case{"box", &MaskDegraderParams::box_rate, &DegradedMaskFrame::boxes},
                        Case{"split", &MaskDegraderParams::split_rate, &DegradedMaskFrame::splits},
                        Case{"switch", &MaskDegraderParams::id_switch_rate, &DegradedMaskFrame::switches},
                        Case{"untracked", &MaskDegraderParams::untracked_rate, &DegradedMaskFrame::untracked}}) {
    MaskDegraderParams p = Nothing();
    p.*c.rate = 0.2;
    MaskDegrader degrader(p);
    int events = 0;
    for (int k = 0; k < kFrames; ++k) events += degrader.degrade(k, exact).*c.count;
    const double n = kFrames * kObjects, rate = events / n;
    // Binomial: 4 standard deviations.
    EXPECT_NEAR(rate, 0.2, 4.0 * std::sqrt(0.2 * 0.8 / n)) << c.name;
  }
  // Small objects are missed more: a 40x40 square is 0.52 % of the image.
  MaskDegraderParams p = Nothing();
  p.miss_rate_small = 0.5, p.small_area_frac = 0.0052;
  MaskDegrader degrader(p);
  int missed = 0;
  for (int k = 0; k < kFrames; ++k) missed += degrader.degrade(k, exact).missed;
  EXPECT_NEAR(missed / double(kFrames * kObjects), 0.5 * std::exp(-1.0), 0.03);
}

TEST(MaskDegrader, NewIdsSayWhereTheyComeFromAndASwitchLasts) {
  MaskDegraderParams p = Nothing();
  p.id_switch_rate = 0.05, p.untracked_rate = 0.05, p.split_rate = 0.05;
  MaskDegrader degrader(p);
  const cv::Mat exact = Squares();
  std::map<int, int> current;  // exact id -> its id in the last frame where it was not untracked or split
  int switches = 0, lasting = 0;
  for (int k = 0; k < 200; ++k) {
    const DegradedMaskFrame d = degrader.degrade(k, exact);
    switches += d.switches;
    for (const auto& [id, source] : d.source_of) {
      EXPECT_EQ(id % kDegradedIdStride, source) << id;
      // The pixels of every id lie on its source object.
      cv::Mat exact32;
      exact.convertTo(exact32, CV_32S);
      EXPECT_EQ(cv::countNonZero((d.ids == id) & (exact32 != source)), 0) << id;
    }
    if (k > 0 && d.switches == 0 && d.untracked == 0)
      for (const auto& [id, source] : d.source_of)
        if (current.count(source) && current[source] == id) ++lasting;
    for (const auto& [id, source] : d.source_of) current[source] = id;
  }
  EXPECT_GT(switches, 20);
  EXPECT_GT(lasting, 400);  // ids, switched or not, carry over from frame to frame
}

TEST(MaskDegrader, IsReproducibleAndItsBoundaryErrorsLowerTheIou) {
  MaskDegraderParams p = Nothing();
  p.boundary_frac = 0.2;
  const cv::Mat exact = Squares();
  MaskDegrader a(p), b(p);
  SegmentationScore score;
  for (int k = 0; k < 50; ++k) {
    const DegradedMaskFrame da = a.degrade(k, exact), db = b.degrade(k, exact);
    EXPECT_EQ(cv::countNonZero(da.ids != db.ids), 0) << k;
    score.add(exact, da.ids, 1);
  }
  // Up to 8 px in or out on a 40 px square: IoU between (24/40)^2 = 0.36 and (40/56)^2 = 0.51 at the extremes.
  EXPECT_LT(score.miou(), 0.9);
  EXPECT_GT(score.miou(), 0.55);
  p.seed = 2;
  MaskDegrader other(p);
  int differ = 0;
  for (int k = 0; k < 10; ++k) differ += cv::countNonZero(other.degrade(k, exact).ids != a.degrade(50 + k, exact).ids) > 0;
  EXPECT_GT(differ, 0);
  p.box_rate = 1.5;
  EXPECT_THROW(MaskDegrader{p}, std::invalid_argument);
}

}  // namespace
}  // namespace dslam
