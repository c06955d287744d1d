#pragma once
// ROS 2 graph presence: a participant tells ROS 2 which nodes it hosts and which of its readers and writers
// each node owns by publishing rmw_dds_common/msg/ParticipantEntitiesInfo on the topic "ros_discovery_info"
// (reliable, transient local, keep last 1, as every rmw does). Without it `ros2 node list` shows nothing
// and `ros2 node info` cannot attribute the topics. Internal to plugin/.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/rtps/common/Guid.h>

#include "plugin/ros_distro.h"

namespace dslam {

class DdsSession;

// An entity's ROS 2 GID: its RTPS GUID (prefix then entity id, as on the wire). Distributions up to Humble
// pad it with zeros to 24 octets.
using RosGid = std::array<uint8_t, 16>;
RosGid ToRosGid(const eprosima::fastrtps::rtps::GUID_t& guid);

struct RosGraphNode {
  std::string node_namespace = "/";  // absolute
  std::string node_name;
  std::vector<RosGid> reader_gids, writer_gids;
};

// The graph topic's writer of one participant: announce() replaces what the graph knows of it.
class RosGraphAnnouncer {
 public:
  // Throws std::runtime_error when the writer cannot be created, std::invalid_argument for an unknown distro.
  RosGraphAnnouncer(DdsSession& session, const std::string& ros_distro);
  void announce(const std::vector<RosGraphNode>& nodes);

 private:
  int gid_width_;
  RosGid participant_gid_;
  eprosima::fastdds::dds::DataWriter* writer_ = nullptr;
};

}  // namespace dslam
