#include "output/frame_overlay.h"

#include <cmath>
#include <cstdio>
#include <map>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

#include "data/image_codec.h"

namespace dslam {
namespace {

cv::Scalar LabelColour(int label) {
  // Well-separated hues for neighbouring labels (the golden angle), bright enough to tint.
  const double hue = std::fmod(label * 137.508, 360.0);
  cv::Mat hsv(1, 1, CV_8UC3, cv::Scalar(hue / 2.0, 200, 255)), bgr;
  cv::cvtColor(hsv, bgr, cv::COLOR_HSV2BGR);
  const cv::Vec3b c = bgr.at<cv::Vec3b>(0, 0);
  return cv::Scalar(c[0], c[1], c[2]);
}

}  // namespace

cv::Mat DrawObjectOverlay(const cv::Mat& image, const cv::Mat& instance_ids,
                          const std::vector<ObjectMotionEstimate>& motions) {
  cv::Mat out;
  if (image.channels() == 1)
    cv::cvtColor(image, out, cv::COLOR_GRAY2BGR);
  else if (image.channels() == 4)
    cv::cvtColor(image, out, cv::COLOR_BGRA2BGR);
  else
    out = image.clone();
  if (!instance_ids.empty()) {
    if (instance_ids.size() != image.size()) throw std::invalid_argument("overlay: mask and image sizes differ");
    cv::Mat ids;
    instance_ids.convertTo(ids, CV_32S);
    cv::Mat tint = out.clone();
    std::map<int, cv::Vec3b> colours;
    for (int v = 0; v < ids.rows; ++v) {
      const int32_t* id = ids.ptr<int32_t>(v);
      cv::Vec3b* t = tint.ptr<cv::Vec3b>(v);
      for (int u = 0; u < ids.cols; ++u) {
        if (id[u] <= 0) continue;
        auto c = colours.find(id[u]);
        if (c == colours.end()) {
          const cv::Scalar s = LabelColour(id[u]);
          c = colours.emplace(id[u], cv::Vec3b(static_cast<uchar>(s[0]), static_cast<uchar>(s[1]), static_cast<uchar>(s[2]))).first;
        }
        t[u] = c->second;
      }
    }
    cv::addWeighted(out, 0.6, tint, 0.4, 0.0, out);
  }
  for (const ObjectMotionEstimate& m : motions) {
    if (!m.image_box) continue;
    const cv::Rect box(m.image_box->x, m.image_box->y, m.image_box->width, m.image_box->height);
    const cv::Scalar colour = m.is_dynamic ? cv::Scalar(60, 220, 60) : cv::Scalar(170, 170, 170);
    cv::rectangle(out, box, colour, 2);
    char text[64];
    if (m.is_dynamic)
      std::snprintf(text, sizeof text, "%d: %.1f m/s", m.object_id, m.speed_mps);
    else
      std::snprintf(text, sizeof text, "%d: standing", m.object_id);
    int baseline = 0;
    const cv::Size size = cv::getTextSize(text, cv::FONT_HERSHEY_SIMPLEX, 0.5, 1, &baseline);
    const cv::Point at(std::max(0, box.x), std::max(size.height + 2, box.y - 3));
    cv::rectangle(out, at + cv::Point(-1, baseline), at + cv::Point(size.width + 1, -size.height - 2), colour, cv::FILLED);
    cv::putText(out, text, at, cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  }
  return out;
}

std::vector<int> OverlayFrames(int frames, int count) {
  std::vector<int> out;
  for (int i = 0; i < count && frames > 0; ++i) {
    const int k = static_cast<int>((2 * i + 1) * static_cast<long>(frames) / (2 * count));
    if (out.empty() || out.back() != k) out.push_back(k);
  }
  return out;
}

void WriteOverlayPng(const cv::Mat& image, const std::string& path) {
  const std::string partial = path + ".partial.png";
  WritePngFile(partial, image, 1, PngFilter::kNone);  // a drawn frame: as small, half the time (image_codec.h)
  if (std::rename(partial.c_str(), path.c_str()) != 0) throw std::runtime_error("cannot replace " + path);
}

}  // namespace dslam
