#include "plugin/sensor_publisher.h"

#include <chrono>
#include <optional>
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

struct EncodedSensorFrame::Messages {
  std::optional<sensor_msgs::msg::CompressedImage> colour_compressed, depth_compressed, mask_compressed;
  std::optional<sensor_msgs::msg::Image> colour, depth, mask;
  std::optional<sensor_msgs::msg::PointCloud2> cloud;
  std::optional<nav_msgs::msg::Odometry> odometry;
};

EncodedSensorFrame::EncodedSensorFrame(std::unique_ptr<Messages> messages) : messages_(std::move(messages)) {}
EncodedSensorFrame::~EncodedSensorFrame() = default;
EncodedSensorFrame::EncodedSensorFrame(EncodedSensorFrame&&) noexcept = default;
EncodedSensorFrame& EncodedSensorFrame::operator=(EncodedSensorFrame&&) noexcept = default;

size_t EncodedSensorFrame::bytes() const {
  size_t n = 0;
  const Messages& m = *messages_;
  for (const auto* c : {&m.colour_compressed, &m.depth_compressed, &m.mask_compressed})
    if (*c) n += (*c)->data().size();
  for (const auto* i : {&m.colour, &m.depth, &m.mask})
    if (*i) n += (*i)->data().size();
  if (m.cloud) n += m.cloud->data().size();
  return n;
}

EncodedSensorFrame SensorPublisher::encode(const ImageFrame& frame, const SE3& T_odom_camera,
                                           const Vec6& twist_sigma_per_s, bool with_odometry,
                                           const std::vector<Eigen::Vector4f>* scan_lidar) const {
  auto m = std::make_unique<EncodedSensorFrame::Messages>();
  if (impl_->compression != ImageCompression::kNone) {
    const auto encode = [&](const cv::Mat& image, ImageRole role) {
      return EncodeCompressedImage(image, role, impl_->compression, frame.t_ns, "camera");
    };
    m->colour_compressed = encode(frame.image, ImageRole::kColour);
    m->depth_compressed = encode(frame.depth_m, ImageRole::kDepth);
    if (!frame.instance_ids.empty()) m->mask_compressed = encode(frame.instance_ids, ImageRole::kMask);
  } else {
    m->colour = EncodeImage(frame.image, ImageRole::kColour, frame.t_ns, "camera");
    m->depth = EncodeImage(frame.depth_m, ImageRole::kDepth, frame.t_ns, "camera");
    if (!frame.instance_ids.empty())
      m->mask = EncodeImage(MaskForTransport(frame.instance_ids), ImageRole::kMask, frame.t_ns, "camera");
  }
  if (impl_->lidar && scan_lidar) m->cloud = EncodePointCloud(*scan_lidar, frame.t_ns, "lidar");
  if (with_odometry) m->odometry = EncodeOdometry(T_odom_camera, frame.t_ns, "odom", "camera", twist_sigma_per_s);
  return EncodedSensorFrame(std::move(m));
}

void SensorPublisher::publish(EncodedSensorFrame& frame, int64_t t_ns) {
  EncodedSensorFrame::Messages& m = *frame.messages_;
  const auto stamp = NsToStamp(t_ns);
  const auto send = [&](dds::DataWriter* writer, auto& message) {
    if (!message) return;
    message->header().stamp(stamp);
    writer->write(&*message);
  };
  send(impl_->colour, m.colour_compressed), send(impl_->depth, m.depth_compressed), send(impl_->mask, m.mask_compressed);
  send(impl_->colour, m.colour), send(impl_->depth, m.depth), send(impl_->mask, m.mask);
  send(impl_->lidar, m.cloud);
  send(impl_->odometry, m.odometry);
}

void SensorPublisher::publish(const ImageFrame& frame, const SE3& T_odom_camera, const Vec6& twist_sigma_per_s,
                              bool with_odometry, const std::vector<Eigen::Vector4f>* scan_lidar) {
  EncodedSensorFrame encoded = encode(frame, T_odom_camera, twist_sigma_per_s, with_odometry, scan_lidar);
  publish(encoded, frame.t_ns);
}

void SensorPublisher::flush() {
  for (dds::DataWriter* w : impl_->writers()) w->wait_for_acknowledgments({10, 0});
}

}  // namespace dslam
