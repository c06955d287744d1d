#pragma once
// Small synthetic images for front-end tests: random textures with corners at every scale, and
// frames of a camera sliding sideways past a textured wall with a textured box moving in front.

#include <random>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

namespace dslam::test {

// Grey texture of random blocks (several sizes) and discs: corners everywhere, no repetition.
inline cv::Mat RandomTexture(int width, int height, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> grey(20, 235);
  cv::Mat image(height, width, CV_8UC1);
  cv::Mat coarse(height / 16 + 1, width / 16 + 1, CV_8UC1), fine(height / 4 + 1, width / 4 + 1, CV_8UC1);
  for (auto* m : {&coarse, &fine})
    for (int v = 0; v < m->rows; ++v)
      for (int u = 0; u < m->cols; ++u) m->at<uint8_t>(v, u) = static_cast<uint8_t>(grey(rng));
  for (int v = 0; v < height; ++v)
    for (int u = 0; u < width; ++u)
      image.at<uint8_t>(v, u) = static_cast<uint8_t>((coarse.at<uint8_t>(v / 16, u / 16) + fine.at<uint8_t>(v / 4, u / 4)) / 2);
  std::uniform_int_distribution<int> x(0, width - 1), y(0, height - 1), r(2, 7);
  for (int i = 0; i < width * height / 400; ++i) cv::circle(image, {x(rng), y(rng)}, r(rng), cv::Scalar(grey(rng)), -1);
  return image;
}

// Sub-pixel translation of an image (content moves by +dx, +dy), border replicated.
inline cv::Mat Shifted(const cv::Mat& image, double dx, double dy) {
  cv::Mat out;
  const cv::Matx23d A(1, 0, dx, 0, 1, dy);
  cv::warpAffine(image, out, A, image.size(), cv::INTER_LINEAR, cv::BORDER_REFLECT);
  return out;
}

}  // namespace dslam::test
