#pragma once
// Internal to plugin/: one DomainParticipant with its publisher and subscriber, types registered, and
// readers/writers created from the named profiles of the XML file (config/dds_profiles.xml):
//   participant "dslam_participant", readers "sensor_reader" and "estimate_reader", writers
//   "sensor_writer" and "estimate_writer".

#include <map>
#include <memory>
#include <string>

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantListener.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/topic/Topic.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>

#include "plugin/dds_error.h"

namespace dslam {

class DdsSession {
 public:
  // Throws DdsStartError naming the profile file or the entity that could not be created. `listener`, when
  // given, hears the participant's discovery from the start and must outlive the session.
  DdsSession(int domain_id, const std::string& profiles_file,
             eprosima::fastdds::dds::DomainParticipantListener* listener = nullptr);
  ~DdsSession();
  DdsSession(const DdsSession&) = delete;
  DdsSession& operator=(const DdsSession&) = delete;

  // `type` is a generated PubSubType, e.g. new sensor_msgs::msg::ImagePubSubType(); registered once per name.
  eprosima::fastdds::dds::DataReader* reader(const std::string& topic, eprosima::fastdds::dds::TopicDataType* type,
                                             const std::string& profile,
                                             eprosima::fastdds::dds::DataReaderListener* listener);
  eprosima::fastdds::dds::DataWriter* writer(const std::string& topic, eprosima::fastdds::dds::TopicDataType* type,
                                             const std::string& profile);
  // The profile's QoS as the XML file gives it (throws DdsStartError when the file has no such profile).
  eprosima::fastdds::dds::DataWriterQos writerQos(const std::string& profile) const;
  // A writer whose QoS a protocol fixes (ROS 2's graph topic), not a profile.
  eprosima::fastdds::dds::DataWriter* writer(const std::string& topic, eprosima::fastdds::dds::TopicDataType* type,
                                             const eprosima::fastdds::dds::DataWriterQos& qos);
  const eprosima::fastrtps::rtps::GUID_t& participantGuid() const { return participant_->guid(); }

 private:
  eprosima::fastdds::dds::Topic* topic(const std::string& name, eprosima::fastdds::dds::TopicDataType* type);

  eprosima::fastdds::dds::DomainParticipant* participant_ = nullptr;
  eprosima::fastdds::dds::Publisher* publisher_ = nullptr;
  eprosima::fastdds::dds::Subscriber* subscriber_ = nullptr;
  std::map<std::string, eprosima::fastdds::dds::TypeSupport> types_;
  std::map<std::string, eprosima::fastdds::dds::Topic*> topics_;
};

}  // namespace dslam
