#include "data/image_frame.h"

#include <opencv2/imgproc.hpp>

namespace dslam {

void SetLidarScan(const std::vector<Eigen::Vector4f>& scan_lidar, const Eigen::Matrix<double, 3, 4>& T_camera_lidar,
                  ImageFrame* frame) {
  const Eigen::Matrix3f R = T_camera_lidar.leftCols<3>().cast<float>();
  const Eigen::Vector3f t = T_camera_lidar.col(3).cast<float>();
  frame->lidar_points_camera.resize(scan_lidar.size());
  for (size_t i = 0; i < scan_lidar.size(); ++i) frame->lidar_points_camera[i] = R * scan_lidar[i].head<3>() + t;
  frame->lidar_origin_camera = t;
  frame->lidar_up_camera = R.col(2);
}

std::string FindInvalidImageFrame(const ImageFrame& frame) {
  const std::string where = "frame " + std::to_string(frame.frame_index) + ": ";
  if (frame.image.empty()) return where + "image is empty";
  if (frame.image.depth() != CV_8U || (frame.image.channels() != 1 && frame.image.channels() != 3 &&
                                       frame.image.channels() != 4))
    return where + "image must be 8-bit grey, BGR or BGRA";
  const cv::Size size = frame.image.size();
  auto size_text = [](const cv::Size& s) { return std::to_string(s.width) + "x" + std::to_string(s.height); };
  if (frame.depth_m.empty()) return where + "depth is missing";
  if (frame.depth_m.type() != CV_32FC1) return where + "depth must be CV_32FC1 metres";
  if (frame.depth_m.size() != size)
    return where + "depth is " + size_text(frame.depth_m.size()) + " but the image is " + size_text(size);
  if (!frame.instance_ids.empty()) {
    if (frame.instance_ids.channels() != 1 ||
        (frame.instance_ids.depth() != CV_16U && frame.instance_ids.depth() != CV_32S))
      return where + "instance mask must be 16-bit unsigned or 32-bit signed, one channel";
    if (frame.instance_ids.size() != size)
      return where + "instance mask is " + size_text(frame.instance_ids.size()) + " but the image is " + size_text(size);
  }
  if (!frame.flow_to_next.empty() && (frame.flow_to_next.type() != CV_32FC2 || frame.flow_to_next.size() != size))
    return where + "flow must be CV_32FC2 of the image size";
  if (frame.odometry) {
    const auto& o = *frame.odometry;
    if (!o.T_prev_curr.translation().allFinite() || !o.T_prev_curr.rotation().coeffs().allFinite())
      return where + "odometry increment is not finite";
    if (!o.sigma.allFinite() || (o.sigma.array() <= 0.0).any()) return where + "odometry sigmas must be positive";
  }
  return {};
}

cv::Mat GreyImage(const cv::Mat& image) {
  if (image.channels() == 1) return image;
  cv::Mat grey;
  cv::cvtColor(image, grey, image.channels() == 4 ? cv::COLOR_BGRA2GRAY : cv::COLOR_BGR2GRAY);
  return grey;
}

}  // namespace dslam
