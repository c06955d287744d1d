#pragma once
// OpenCV's edge-aware weighted-least-squares disparity filter (ximgproc, from OpenCV's contrib modules), built
// as a module of its own (libdslam_ximgproc.so, loaded on first use: data/runtime_module.h). ximgproc links
// OpenCV's image codecs and through them GDAL: ~110 libraries every process would load at start-up for a
// filter that is off by default.

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

#include "data/runtime_module.h"

namespace dslam {

// Filters the left matcher's fixed-point disparities (4 fractional bits) guided by the left grey image, with
// the right image's disparities for the left-right confidence. *confidence: CV_32F, 0..255.
void WlsFilterWithXimgproc(const cv::Ptr<cv::StereoMatcher>& left_matcher, const cv::Mat& left16,
                           const cv::Mat& left_grey, const cv::Mat& right16, double lambda, double sigma_color,
                           cv::Mat* filtered16, cv::Mat* confidence);

// What the module exports (stereo_wls_module.cpp). Raise kVersion when a signature changes.
struct XimgprocFunctions {
  static constexpr int kVersion = 1;
  ModuleTableHeader header;
  decltype(&WlsFilterWithXimgproc) wls_filter = nullptr;
};

inline const XimgprocFunctions& Ximgproc() {
  return RuntimeModuleTable<XimgprocFunctions>("dslam_ximgproc", "dslam_ximgproc_functions");
}

}  // namespace dslam

extern "C" const dslam::XimgprocFunctions* dslam_ximgproc_functions();
