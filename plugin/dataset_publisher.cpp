#include "plugin/dataset_publisher.h"

#include <chrono>
#include <thread>

#include "nav_msgs_OdometryPubSubTypes.h"
#include "plugin/dds_session.h"
#include "plugin/image_message.h"
#include "plugin/topics.h"
#include "sensor_msgs_ImagePubSubTypes.h"

namespace dslam {
namespace dds = eprosima::fastdds::dds;

int PublishDataset(const ImageDataset& dataset, const PublishOptions& options, std::ostream& log,
                   const std::atomic<bool>* stop) {
  if (!(options.rate_hz > 0.0)) throw std::invalid_argument("--rate must be positive");
  if (options.start_frame < 0 || options.start_frame >= dataset.size())
    throw std::invalid_argument("--start-frame " + std::to_string(options.start_frame) + " is outside the " +
                                std::to_string(dataset.size()) + " frames");
  DdsSession session(options.domain_id, options.profiles_file);
  const VehicleTopics topics = TopicsFor(options.vehicle);
  dds::DataWriter* colour = session.writer(topics.colour, new sensor_msgs::msg::ImagePubSubType(), "sensor_writer");
  dds::DataWriter* depth = session.writer(topics.depth, new sensor_msgs::msg::ImagePubSubType(), "sensor_writer");
  dds::DataWriter* mask = session.writer(topics.mask, new sensor_msgs::msg::ImagePubSubType(), "sensor_writer");
  dds::DataWriter* odometry = session.writer(topics.odometry, new nav_msgs::msg::OdometryPubSubType(), "sensor_writer");

  // Wait until someone listens on every input topic (discovery takes a moment).
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(options.wait_for_reader_s);
  for (;;) {
    bool all = true;
    for (dds::DataWriter* w : {colour, depth, mask, odometry}) {
      dds::PublicationMatchedStatus matched;
      w->get_publication_matched_status(matched);
      all = all && matched.current_count > 0;
    }
    if (all || std::chrono::steady_clock::now() > deadline || (stop && *stop)) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }

  // The vehicle's pose in its odometry frame, accumulated from the increments.
  SE3 T_odom_camera;
  for (int k = 1; k < options.start_frame; ++k) {
    const ImageFrame f = dataset.read(k);  // only its odometry is needed; datasets are small enough
    if (f.odometry) T_odom_camera = T_odom_camera * f.odometry->T_prev_curr;
  }
  const int end = options.frames > 0 ? std::min(dataset.size(), options.start_frame + options.frames) : dataset.size();
  const auto period = std::chrono::duration<double>(1.0 / options.rate_hz);
  auto next = std::chrono::steady_clock::now();
  int published = 0;
  for (int k = options.start_frame; k < end && !(stop && *stop); ++k) {
    const ImageFrame frame = dataset.read(k);
    Vec6 sigma = Vec6::Constant(0.01);  // the first frame's pose starts the chain; its sigma is not used
    if (frame.odometry) {
      T_odom_camera = T_odom_camera * frame.odometry->T_prev_curr;
      sigma = frame.odometry->sigma;
    }
    sensor_msgs::msg::Image colour_msg = EncodeImage(frame.image, ImageRole::kColour, frame.t_ns, "camera");
    sensor_msgs::msg::Image depth_msg = EncodeImage(frame.depth_m, ImageRole::kDepth, frame.t_ns, "camera");
    colour->write(&colour_msg);
    depth->write(&depth_msg);
    if (!frame.instance_ids.empty()) {
      cv::Mat ids;
      frame.instance_ids.convertTo(ids, CV_16U);
      sensor_msgs::msg::Image mask_msg = EncodeImage(ids, ImageRole::kMask, frame.t_ns, "camera");
      mask->write(&mask_msg);
    }
    if (dataset.hasOdometry()) {
      nav_msgs::msg::Odometry odom = EncodeOdometry(T_odom_camera, frame.t_ns, "odom", "camera", sigma);
      odometry->write(&odom);
    }
    ++published;
    if ((k + 1) % 10 == 0 || k + 1 == end) log << "  published frame " << k + 1 << "/" << end << std::endl;
    next += std::chrono::duration_cast<std::chrono::steady_clock::duration>(period);
    std::this_thread::sleep_until(next);
  }
  // Let reliable writers deliver what is queued before the participant goes.
  for (dds::DataWriter* w : {colour, depth, mask, odometry}) w->wait_for_acknowledgments({2, 0});
  return published;
}

}  // namespace dslam
