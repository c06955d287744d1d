// libdslam_ximgproc.so (data/stereo_wls.h): the only code that includes OpenCV's ximgproc.
#include <opencv2/ximgproc/disparity_filter.hpp>

#include "data/stereo_wls.h"

namespace dslam {

void WlsFilterWithXimgproc(const cv::Ptr<cv::StereoMatcher>& left_matcher, const cv::Mat& left16,
                           const cv::Mat& left_grey, const cv::Mat& right16, double lambda, double sigma_color,
                           cv::Mat* filtered16, cv::Mat* confidence) {
  auto wls = cv::ximgproc::createDisparityWLSFilter(left_matcher);
  wls->setLambda(lambda);
  wls->setSigmaColor(sigma_color);
  wls->filter(left16, left_grey, *filtered16, right16);
  *confidence = wls->getConfidenceMap();  // 0 where the left-right check failed
}

}  // namespace dslam

extern "C" __attribute__((visibility("default"))) const dslam::XimgprocFunctions* dslam_ximgproc_functions() {
  static const dslam::XimgprocFunctions functions{
      {dslam::XimgprocFunctions::kVersion, sizeof(dslam::XimgprocFunctions)}, &dslam::WlsFilterWithXimgproc};
  return &functions;
}
