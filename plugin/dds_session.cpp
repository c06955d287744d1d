#include "plugin/dds_session.h"

#include <memory>
#include <mutex>
#include <stdexcept>
#include <vector>

#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/log/Log.hpp>

namespace dslam {
namespace dds = eprosima::fastdds::dds;
namespace {

// While DDS starts, Fast DDS' own error lines (coloured, several per failure) are captured instead of printed,
// so that a failure is one line of ours that quotes the first of them. Fast DDS' logging is restored after.
class StartupLog {
 public:
  StartupLog() {
    dds::Log::ClearConsumers();
    dds::Log::RegisterConsumer(std::make_unique<Consumer>(this));
  }
  ~StartupLog() {
    dds::Log::Flush();
    dds::Log::Reset();
  }
  // ": <Fast DDS' first error>" when it logged one, else empty.
  std::string firstError() {
    dds::Log::Flush();
    const std::lock_guard<std::mutex> lock(mutex_);
    return errors_.empty() ? std::string() : ": " + errors_.front();
  }

 private:
  class Consumer : public dds::LogConsumer {
   public:
    explicit Consumer(StartupLog* log) : log_(log) {}
    void Consume(const dds::Log::Entry& entry) override {
      if (entry.kind != dds::Log::Kind::Error) return;
      const std::lock_guard<std::mutex> lock(log_->mutex_);
      log_->errors_.push_back(entry.message);
    }

   private:
    StartupLog* log_;
  };
  std::mutex mutex_;
  std::vector<std::string> errors_;
};

}  // namespace

DdsSession::DdsSession(int domain_id, const std::string& profiles_file, dds::DomainParticipantListener* listener) {
  StartupLog log;
  auto* factory = dds::DomainParticipantFactory::get_instance();
  if (factory->load_XML_profiles_file(profiles_file) != ReturnCode_t::RETCODE_OK)
    throw DdsStartError("cannot load the Fast DDS profiles " + profiles_file + log.firstError());
  // Discovery callbacks only (none of the listener's data callbacks: the endpoints have their own).
  participant_ = factory->create_participant_with_profile(static_cast<dds::DomainId_t>(domain_id), "dslam_participant",
                                                          listener, dds::StatusMask::none());
  if (!participant_)
    throw DdsStartError("cannot create a DDS participant on domain " + std::to_string(domain_id) +
                        " (profile dslam_participant of " + profiles_file + ")" + log.firstError());
  publisher_ = participant_->create_publisher(dds::PUBLISHER_QOS_DEFAULT);
  subscriber_ = participant_->create_subscriber(dds::SUBSCRIBER_QOS_DEFAULT);
  if (!publisher_ || !subscriber_) throw DdsStartError("cannot create the DDS publisher and subscriber");
}

DdsSession::~DdsSession() {
  if (participant_) {
    participant_->delete_contained_entities();
    dds::DomainParticipantFactory::get_instance()->delete_participant(participant_);
  }
}

dds::Topic* DdsSession::topic(const std::string& name, dds::TopicDataType* type) {
  const std::string type_name = type->getName();
  auto t = types_.find(type_name);
  if (t == types_.end()) {
    t = types_.emplace(type_name, dds::TypeSupport(type)).first;
    if (t->second.register_type(participant_) != ReturnCode_t::RETCODE_OK)
      throw DdsStartError("cannot register DDS type " + type_name);
  } else {
    delete type;  // already registered under this name
  }
  auto it = topics_.find(name);
  if (it != topics_.end()) return it->second;
  dds::Topic* topic = participant_->create_topic(name, type_name, dds::TOPIC_QOS_DEFAULT);
  if (!topic) throw DdsStartError("cannot create DDS topic " + name);
  topics_[name] = topic;
  return topic;
}

dds::DataReader* DdsSession::reader(const std::string& topic_name, dds::TopicDataType* type, const std::string& profile,
                                    dds::DataReaderListener* listener) {
  dds::DataReader* r = subscriber_->create_datareader_with_profile(topic(topic_name, type), profile, listener);
  if (!r) throw DdsStartError("cannot create a reader of " + topic_name + " with profile " + profile);
  return r;
}

dds::DataWriter* DdsSession::writer(const std::string& topic_name, dds::TopicDataType* type, const std::string& profile) {
  dds::DataWriter* w = publisher_->create_datawriter_with_profile(topic(topic_name, type), profile);
  if (!w) throw DdsStartError("cannot create a writer of " + topic_name + " with profile " + profile);
  return w;
}

dds::DataWriterQos DdsSession::writerQos(const std::string& profile) const {
  dds::DataWriterQos qos;
  if (publisher_->get_datawriter_qos_from_profile(profile, qos) != ReturnCode_t::RETCODE_OK)
    throw DdsStartError("the profiles have no data_writer profile '" + profile + "'");
  return qos;
}

dds::DataWriter* DdsSession::writer(const std::string& topic_name, dds::TopicDataType* type,
                                    const dds::DataWriterQos& qos) {
  dds::DataWriter* w = publisher_->create_datawriter(topic(topic_name, type), qos);
  if (!w) throw DdsStartError("cannot create a writer of " + topic_name);
  return w;
}

}  // namespace dslam
