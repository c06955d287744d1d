#include "plugin/estimate_listener.h"

#include <mutex>

#include <fastdds/dds/subscriber/SampleInfo.hpp>

#include "nav_msgs_OdometryPubSubTypes.h"
#include "plugin/dds_session.h"
#include "plugin/image_message.h"
#include "plugin/topics.h"

namespace dslam {
namespace dds = eprosima::fastdds::dds;

struct CameraEstimateListener::Impl : dds::DataReaderListener {
  mutable std::mutex mutex;
  std::map<int64_t, Clock::time_point> at;
  DdsSession session;

  Impl(int domain_id, const std::string& profiles) : session(domain_id, profiles) {}
  void on_data_available(dds::DataReader* reader) override {
    nav_msgs::msg::Odometry msg;
    dds::SampleInfo info;
    while (reader->take_next_sample(&msg, &info) == ReturnCode_t::RETCODE_OK)
      if (info.valid_data) {
        std::lock_guard<std::mutex> lock(mutex);
        at[StampToNs(msg.header().stamp())] = Clock::now();
      }
  }
};

CameraEstimateListener::CameraEstimateListener(int domain_id, const std::string& profiles_file, const std::string& vehicle)
    : impl_(std::make_unique<Impl>(domain_id, profiles_file)) {
  impl_->session.reader(TopicsFor(vehicle).camera_odometry, new nav_msgs::msg::OdometryPubSubType(), "estimate_reader",
                        impl_.get());
}

CameraEstimateListener::~CameraEstimateListener() = default;

std::map<int64_t, CameraEstimateListener::Clock::time_point> CameraEstimateListener::receipts() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->at;
}

}  // namespace dslam
