#include "plugin/sensor_publisher.h"

#include <chrono>
#include <thread>

#include "nav_msgs_OdometryPubSubTypes.h"
#include "plugin/dds_session.h"
#include "plugin/image_message.h"
#include "plugin/point_cloud_message.h"
#include "plugin/topics.h"
#include "sensor_msgs_CompressedImagePubSubTypes.h"
#include "sensor_msgs_ImagePubSubTypes.h"
#include "sensor_msgs_PointCloud2PubSubTypes.h"

namespace dslam {
namespace dds = eprosima::fastdds::dds;

struct SensorPublisher::Impl {
  DdsSession session;
  dds::DataWriter *colour = nullptr, *depth = nullptr, *mask = nullptr, *odometry = nullptr, *lidar = nullptr;
  std::vector<dds::DataWriter*> writers() const {
    std::vector<dds::DataWriter*> all = {colour, depth, mask, odometry};
    if (lidar) all.push_back(lidar);
    return all;
  }
  ImageCompression compression = ImageCompression::kNone;
  Impl(int domain_id, const std::string& profiles) : session(domain_id, profiles) {}
};

SensorPublisher::SensorPublisher(int domain_id, const std::string& profiles_file, const std::string& vehicle,
                                 bool with_lidar, ImageCompression compression)
    : impl_(std::make_unique<Impl>(domain_id, profiles_file)) {
  const VehicleTopics topics = TopicsFor(vehicle);
  auto& s = impl_->session;
  impl_->compression = compression;
  if (compression == ImageCompression::kNone) {
    impl_->colour = s.writer(topics.colour, new sensor_msgs::msg::ImagePubSubType(), "sensor_writer");
    impl_->depth = s.writer(topics.depth, new sensor_msgs::msg::ImagePubSubType(), "sensor_writer");
    impl_->mask = s.writer(topics.mask, new sensor_msgs::msg::ImagePubSubType(), "sensor_writer");
  } else {
    impl_->colour = s.writer(topics.colour_compressed, new sensor_msgs::msg::CompressedImagePubSubType(), "sensor_writer");
    impl_->depth = s.writer(topics.depth_compressed, new sensor_msgs::msg::CompressedImagePubSubType(), "sensor_writer");
    impl_->mask = s.writer(topics.mask_compressed, new sensor_msgs::msg::CompressedImagePubSubType(), "sensor_writer");
  }
  impl_->odometry = s.writer(topics.odometry, new nav_msgs::msg::OdometryPubSubType(), "sensor_writer");
  if (with_lidar) impl_->lidar = s.writer(topics.lidar, new sensor_msgs::msg::PointCloud2PubSubType(), "sensor_writer");
}

SensorPublisher::~SensorPublisher() = default;

bool SensorPublisher::waitForReaders(double timeout_s, const std::atomic<bool>* stop) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  for (;;) {
    bool all = true;
    for (dds::DataWriter* w : impl_->writers()) {
      dds::PublicationMatchedStatus matched;
      w->get_publication_matched_status(matched);
      all = all && matched.current_count > 0;
    }
    if (all) return true;
    if (std::chrono::steady_clock::now() > deadline || (stop && *stop)) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
}

void SensorPublisher::publish(const ImageFrame& frame, const SE3& T_odom_camera, const Vec6& twist_sigma_per_s,
                              bool with_odometry, const std::vector<Eigen::Vector4f>* scan_lidar) {
  if (impl_->compression != ImageCompression::kNone) {
    const auto write = [&](dds::DataWriter* writer, const cv::Mat& image, ImageRole role) {
      sensor_msgs::msg::CompressedImage msg = EncodeCompressedImage(image, role, impl_->compression, frame.t_ns, "camera");
      writer->write(&msg);
    };
    write(impl_->colour, frame.image, ImageRole::kColour);
    write(impl_->depth, frame.depth_m, ImageRole::kDepth);
    if (!frame.instance_ids.empty()) write(impl_->mask, frame.instance_ids, ImageRole::kMask);
  } else {
    sensor_msgs::msg::Image colour = EncodeImage(frame.image, ImageRole::kColour, frame.t_ns, "camera");
    sensor_msgs::msg::Image depth = EncodeImage(frame.depth_m, ImageRole::kDepth, frame.t_ns, "camera");
    impl_->colour->write(&colour);
    impl_->depth->write(&depth);
    if (!frame.instance_ids.empty()) {
      sensor_msgs::msg::Image mask = EncodeImage(MaskForTransport(frame.instance_ids), ImageRole::kMask, frame.t_ns, "camera");
      impl_->mask->write(&mask);
    }
  }
  if (impl_->lidar && scan_lidar) {
    sensor_msgs::msg::PointCloud2 cloud = EncodePointCloud(*scan_lidar, frame.t_ns, "lidar");
    impl_->lidar->write(&cloud);
  }
  if (with_odometry) {
    nav_msgs::msg::Odometry odometry = EncodeOdometry(T_odom_camera, frame.t_ns, "odom", "camera", twist_sigma_per_s);
    impl_->odometry->write(&odometry);
  }
}

void SensorPublisher::flush() {
  for (dds::DataWriter* w : impl_->writers()) w->wait_for_acknowledgments({10, 0});
}

}  // namespace dslam
