#include "plugin/ros_graph.h"

#include <algorithm>
#include <stdexcept>

#include "plugin/dds_session.h"
#include "rmw_dds_common_ParticipantEntitiesInfoPubSubTypes.h"

namespace dslam {
namespace dds = eprosima::fastdds::dds;

namespace {

constexpr const char* kGraphTopic = "ros_discovery_info";  // no "rt/": not a ROS topic
constexpr const char* kGraphTypeName = "rmw_dds_common::msg::dds_::ParticipantEntitiesInfo_";

// Fills a message of either layout (Humble's 24-octet GIDs or the later 16-octet ones).
template <typename Message, typename NodeInfo, typename Gid>
Message GraphMessage(const RosGid& participant, const std::vector<RosGraphNode>& nodes) {
  auto gid = [](const RosGid& g) {
    Gid out;
    out.data().fill(0);
    std::copy(g.begin(), g.end(), out.data().begin());
    return out;
  };
  Message msg;
  msg.gid(gid(participant));
  for (const RosGraphNode& n : nodes) {
    NodeInfo info;
    info.node_namespace(n.node_namespace);
    info.node_name(n.node_name);
    for (const RosGid& g : n.reader_gids) info.reader_gid_seq().push_back(gid(g));
    for (const RosGid& g : n.writer_gids) info.writer_gid_seq().push_back(gid(g));
    msg.node_entities_info_seq().push_back(info);
  }
  return msg;
}

}  // namespace

RosGid ToRosGid(const eprosima::fastrtps::rtps::GUID_t& guid) {
  RosGid gid{};
  std::copy(guid.guidPrefix.value, guid.guidPrefix.value + 12, gid.begin());
  std::copy(guid.entityId.value, guid.entityId.value + 4, gid.begin() + 12);
  return gid;
}

RosGraphAnnouncer::RosGraphAnnouncer(DdsSession& session, const std::string& ros_distro)
    : gid_width_(RosGidWidth(ros_distro)), participant_gid_(ToRosGid(session.participantGuid())) {
  dds::TopicDataType* type = nullptr;
  if (gid_width_ == 24) {
    type = new rmw_dds_common_humble::msg::ParticipantEntitiesInfoPubSubType();
    type->setName(kGraphTypeName);  // the layout of Humble's rmw_dds_common, under its DDS name
  } else {
    type = new rmw_dds_common::msg::ParticipantEntitiesInfoPubSubType();
  }
  // What every rmw uses for this topic: a late-joining `ros2` daemon still gets the participant's last sample.
  dds::DataWriterQos qos = dds::DATAWRITER_QOS_DEFAULT;
  qos.reliability().kind = dds::RELIABLE_RELIABILITY_QOS;
  qos.durability().kind = dds::TRANSIENT_LOCAL_DURABILITY_QOS;
  qos.history().kind = dds::KEEP_LAST_HISTORY_QOS;
  qos.history().depth = 1;
  writer_ = session.writer(kGraphTopic, type, qos);
}

void RosGraphAnnouncer::announce(const std::vector<RosGraphNode>& nodes) {
  bool written = false;
  if (gid_width_ == 24) {
    namespace m = rmw_dds_common_humble::msg;
    auto msg = GraphMessage<m::ParticipantEntitiesInfo, m::NodeEntitiesInfo, m::Gid>(participant_gid_, nodes);
    written = writer_->write(&msg);
  } else {
    namespace m = rmw_dds_common::msg;
    auto msg = GraphMessage<m::ParticipantEntitiesInfo, m::NodeEntitiesInfo, m::Gid>(participant_gid_, nodes);
    written = writer_->write(&msg);
  }
  if (!written) throw std::runtime_error(std::string("cannot write the ROS 2 graph sample on ") + kGraphTopic);
}

}  // namespace dslam
