#include "data/runtime_module.h"

#include <gtest/gtest.h>

#include <cstdlib>

#include <opencv2/calib3d.hpp>

#include "data/depth_maps.h"
#include "data/stereo_wls.h"

namespace dslam {
namespace {

TEST(RuntimeModule, AMissingModuleIsAClearErrorNamingWhereItLooked) {
  EXPECT_FALSE(RuntimeModuleLoaded("dslam_no_such_module"));
  try {
    RuntimeModuleSymbol("dslam_no_such_module", "entry");
    ADD_FAILURE() << "a missing module was loaded";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("libdslam_no_such_module.so"), std::string::npos) << what;
    EXPECT_NE(what.find(DSLAM_BINARY_DIR), std::string::npos) << what;  // the build tree is searched
  }
}

TEST(RuntimeModule, AModuleWithoutTheEntryIsRefused) {
  try {
    RuntimeModuleSymbol("dslam_ximgproc", "no_such_entry");
    ADD_FAILURE() << "a missing symbol was found";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("no_such_entry"), std::string::npos) << e.what();
  }
}

// The WLS filter's module is mapped only when a depth is filtered with it. Checked in a process of its own
// (gtest's "threadsafe" death tests start the test binary afresh): another test may have loaded it already.
int StereoFilterLoadOrder() {
  cv::Mat left(60, 120, CV_8UC1), right = cv::Mat::zeros(60, 120, CV_8UC1);
  cv::randu(left, 0, 255);
  left(cv::Rect(4, 0, 116, 60)).copyTo(right(cv::Rect(0, 0, 116, 60)));  // 4 px of disparity everywhere
  StereoParams params;
  params.num_disparities = 16;
  DepthFromStereo(left, right, 700.0, 0.5, params);
  if (RuntimeModuleLoaded("dslam_ximgproc")) return 1;
  params.filter = "wls";
  if (DepthFromStereo(left, right, 700.0, 0.5, params).size() != left.size()) return 2;
  return RuntimeModuleLoaded("dslam_ximgproc") ? 0 : 3;
}

TEST(RuntimeModule, TheStereoFilterModuleLoadsOnFirstUseOnly) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  // 1: loaded without the filter; 2: a depth of the wrong size; 3: not loaded by the filter.
  EXPECT_EXIT(std::exit(StereoFilterLoadOrder()), ::testing::ExitedWithCode(0), "");
}

}  // namespace
}  // namespace dslam
