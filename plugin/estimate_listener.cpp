#include "plugin/estimate_listener.h"

#include <cstdio>
#include <mutex>

#include <fastdds/dds/subscriber/SampleInfo.hpp>

#include "nav_msgs_OdometryPubSubTypes.h"
#include "plugin/dds_session.h"
#include "plugin/image_message.h"
#include "plugin/topics.h"

namespace dslam {
namespace dds = eprosima::fastdds::dds;

namespace {
std::string GuidHex(const eprosima::fastrtps::rtps::GUID_t& guid) {
  std::string s;
  char byte[3];
  for (auto v : guid.guidPrefix.value) std::snprintf(byte, sizeof(byte), "%02x", v), s += byte;
  for (auto v : guid.entityId.value) std::snprintf(byte, sizeof(byte), "%02x", v), s += byte;
  return s;
}
}  // namespace

struct CameraEstimateListener::Impl : dds::DataReaderListener {
  mutable std::mutex mutex;
  std::map<int64_t, Clock::time_point> at;
  int matched = 0, alive = -1;
  Callback on_estimate;
  DdsSession session;

  Impl(int domain_id, const std::string& profiles, Callback callback)
      : on_estimate(std::move(callback)), session(domain_id, profiles) {}
  void on_data_available(dds::DataReader* reader) override {
    nav_msgs::msg::Odometry msg;
    dds::SampleInfo info;
    while (reader->take_next_sample(&msg, &info) == ReturnCode_t::RETCODE_OK) {
      if (!info.valid_data) continue;
      const auto now = Clock::now();
      const int64_t t_ns = StampToNs(msg.header().stamp());
      {
        std::lock_guard<std::mutex> lock(mutex);
        at[t_ns] = now;
      }
      if (!on_estimate) continue;
      ReceivedEstimate e;
      e.stamp_ns = t_ns;
      e.received_unix_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(
                               std::chrono::system_clock::now().time_since_epoch()).count();
      e.writer = GuidHex(info.sample_identity.writer_guid());
      std::string error;
      if (const auto pose = DecodeOdometry(msg, &error)) e.T_world_camera = pose->T_odom_camera;
      on_estimate(e);
    }
  }
  void on_subscription_matched(dds::DataReader*, const dds::SubscriptionMatchedStatus& status) override {
    std::lock_guard<std::mutex> lock(mutex);
    matched = status.current_count;
  }
  void on_liveliness_changed(dds::DataReader*, const dds::LivelinessChangedStatus& status) override {
    std::lock_guard<std::mutex> lock(mutex);
    alive = status.alive_count;
  }
};

CameraEstimateListener::CameraEstimateListener(int domain_id, const std::string& profiles_file, const std::string& vehicle,
                                               Callback on_estimate)
    : impl_(std::make_unique<Impl>(domain_id, profiles_file, std::move(on_estimate))) {
  impl_->session.reader(TopicsFor(vehicle).camera_odometry, new nav_msgs::msg::OdometryPubSubType(), "estimate_reader",
                        impl_.get());
}

CameraEstimateListener::~CameraEstimateListener() = default;

std::map<int64_t, CameraEstimateListener::Clock::time_point> CameraEstimateListener::receipts() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->at;
}

int CameraEstimateListener::aliveWriters() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->alive;
}

int CameraEstimateListener::matchedWriters() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->matched;
}

}  // namespace dslam
