// serve in the ROS 2 graph, as `ros2 node list` and `ros2 node info` see it: a Cyclone DDS client
// (tests/interop/cyclone_graph_reader.c) reads ros_discovery_info in one distribution's GID layout and the
// DDS discovery of every endpoint, over UDP with shared memory off on the Fast DDS side.
#include <gtest/gtest.h>
#include <signal.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "support/child_process.h"
#include "support/dds_domain.h"
#include "support/dds_profiles.h"
#include "support/temp_paths.h"

namespace dslam {
namespace {
using namespace std::chrono_literals;

struct Endpoint {
  std::string participant, topic, type;
};
struct GraphNode {
  std::string node_namespace, name;
  std::vector<std::string> readers, writers;  // GIDs, hex
};
struct Graph {
  std::string participant;  // hex
  std::vector<GraphNode> nodes;
  std::map<std::string, Endpoint> publications, subscriptions;  // by GUID, hex
};

Graph ReadGraph(const std::string& path) {
  Graph g;
  std::ifstream in(path);
  for (std::string line; std::getline(in, line);) {
    std::istringstream f(line);
    std::string kind;
    f >> kind;
    if (kind == "participant") {
      f >> g.participant;
    } else if (kind == "node") {
      GraphNode n;
      f >> n.node_namespace >> n.name;
      g.nodes.push_back(n);
    } else if (kind == "reader" || kind == "writer") {
      std::string gid;
      f >> gid;
      if (g.nodes.empty()) ADD_FAILURE() << "an endpoint before any node: " << line;
      else (kind == "reader" ? g.nodes.back().readers : g.nodes.back().writers).push_back(gid);
    } else if (kind == "publication" || kind == "subscription") {
      std::string guid;
      Endpoint e;
      f >> guid >> e.participant >> e.topic >> e.type;
      (kind == "publication" ? g.publications : g.subscriptions)[guid] = e;
    } else {
      ADD_FAILURE() << path << ": unexpected line: " << line;
    }
  }
  return g;
}

std::string Calibration(const std::string& dir) {
  std::filesystem::create_directories(dir);
  std::ofstream(dir + "/calib.txt") << "P0: 721.5 0 609.6 0 0 721.5 172.9 0 0 0 1 0\n"
                                    << "P2: 721.5 0 609.6 0 0 721.5 172.9 0 0 0 1 0\n"
                                    << "R0_rect: 1 0 0 0 1 0 0 0 1\n";
  return dir + "/calib.txt";
}

// serve with `extra` options on `domain` over UDP only, until SIGTERM.
std::unique_ptr<test::Process> StartServe(int domain, const std::string& name, const std::vector<std::string>& extra) {
  const std::string dir = test::TempPath(name);
  const std::string profiles = test::WithoutSharedMemory(std::string(DSLAM_SOURCE_DIR) + "/config/dds_profiles.xml",
                                                         test::TempPath(name + "_udp.xml"));
  std::vector<std::string> args = {"serve", "--domain", std::to_string(domain), "--profiles", profiles, "--calib",
                                   Calibration(dir), "--out", dir + "/out", "--status-every", "0"};
  args.insert(args.end(), extra.begin(), extra.end());
  return std::make_unique<test::Process>(args, dir + "_serve.log");
}

// The graph as a client reading `gid_width`-octet GIDs sees it within `timeout_s`; the reader's exit status
// in `status`.
Graph ReadGraphWith(int domain, int gid_width, int nodes, const std::string& name, int* status, int timeout_s = 60) {
  const std::string path = test::TempPath(name + ".txt");
  test::Process reader(DSLAM_CYCLONE_GRAPH_READER,
                       {std::to_string(domain), std::to_string(gid_width), std::to_string(nodes), std::to_string(timeout_s), path},
                       test::TempPath(name + ".log"));
  *status = reader.wait(std::chrono::seconds(timeout_s + 30));
  return ReadGraph(path);
}

// What `ros2 node info` lists for a node of serve's: its endpoints' topics and types, found by their GIDs in
// DDS discovery, each owned by the participant the graph sample describes. A GID is the RTPS GUID, padded with
// zeros to `gid_width` octets.
std::map<std::string, std::string> NodeTopics(const Graph& g, const GraphNode& n, int gid_width, bool writers) {
  std::map<std::string, std::string> topics;  // topic -> type
  for (const std::string& gid : writers ? n.writers : n.readers) {
    EXPECT_EQ(gid.size(), 2u * gid_width) << gid;
    EXPECT_EQ(gid.substr(32), std::string(2 * gid_width - 32, '0')) << gid;
    const auto& endpoints = writers ? g.publications : g.subscriptions;
    const auto it = endpoints.find(gid.substr(0, 32));
    if (it == endpoints.end()) {
      ADD_FAILURE() << "GID " << gid << " of " << n.node_namespace << "/" << n.name << " names no discovered endpoint";
      continue;
    }
    EXPECT_EQ(it->second.participant, g.participant.substr(0, 32)) << it->second.topic;
    topics[it->second.topic] = it->second.type;
  }
  return topics;
}

// Jazzy's layout (the default): one node per vehicle, in the vehicle's namespace, owning exactly that
// vehicle's four inputs and four outputs.
TEST(RosGraph, ServeShowsOneNodePerVehicleOwningItsTopicsInJazzysLayout) {
  const int domain = test::DomainFor(test::DdsTestSlot::kRosGraphJazzy);
  auto serve = StartServe(domain, "ros_graph_jazzy", {"--vehicle", "car1", "--vehicle", "car2"});
  int status = -1;
  const Graph g = ReadGraphWith(domain, 16, 2, "ros_graph_jazzy_reader", &status);
  serve->signal(SIGTERM);
  EXPECT_EQ(serve->wait(60s), 0) << test::ReadFile(test::TempPath("ros_graph_jazzy") + "_serve.log");
  ASSERT_EQ(status, 0) << test::ReadFile(test::TempPath("ros_graph_jazzy_reader.log"));

  ASSERT_EQ(g.participant.size(), 32u);
  ASSERT_EQ(g.nodes.size(), 2u);
  for (const GraphNode& n : g.nodes) {
    ASSERT_TRUE(n.node_namespace == "/car1" || n.node_namespace == "/car2") << n.node_namespace;
    EXPECT_EQ(n.name, "dslam");
    const std::string ns = "rt" + n.node_namespace + "/";
    const std::map<std::string, std::string> subscriptions = {
        {ns + "camera/color/image_raw", "sensor_msgs::msg::dds_::Image_"},
        {ns + "camera/depth/image_raw", "sensor_msgs::msg::dds_::Image_"},
        {ns + "camera/instance_mask", "sensor_msgs::msg::dds_::Image_"},
        {ns + "camera/color/image_raw/compressed", "sensor_msgs::msg::dds_::CompressedImage_"},
        {ns + "camera/depth/image_raw/compressed", "sensor_msgs::msg::dds_::CompressedImage_"},
        {ns + "camera/instance_mask/compressed", "sensor_msgs::msg::dds_::CompressedImage_"},
        {ns + "odom", "nav_msgs::msg::dds_::Odometry_"}};
    const std::map<std::string, std::string> publications = {
        {ns + "dslam/camera_odometry", "nav_msgs::msg::dds_::Odometry_"},
        {ns + "dslam/object_motions", "dslam_msgs::msg::dds_::ObjectMotionArray_"},
        {ns + "dslam/status", "dslam_msgs::msg::dds_::Status_"},
        {ns + "dslam/markers", "visualization_msgs::msg::dds_::MarkerArray_"}};
    EXPECT_EQ(n.readers.size(), 7u);  // the images raw and compressed, and the odometry
    EXPECT_EQ(n.writers.size(), 4u);
    EXPECT_EQ(NodeTopics(g, n, 16, false), subscriptions) << n.node_namespace;
    EXPECT_EQ(NodeTopics(g, n, 16, true), publications) << n.node_namespace;
  }
  EXPECT_NE(g.nodes[0].node_namespace, g.nodes[1].node_namespace);
}

// Humble's layout on request, with a node name given: the GIDs are padded to 24 octets. A client reading
// Jazzy's layout sees no node at all in it: the distribution has to match, which is why it is an option.
TEST(RosGraph, ServeSpeaksHumblesLayoutWhenAskedAndAJazzyReaderSeesNoNodeInIt) {
  const int domain = test::DomainFor(test::DdsTestSlot::kRosGraphHumble);
  auto serve = StartServe(domain, "ros_graph_humble", {"--ros-distro", "humble", "--node-name", "estimator"});
  int status = -1;
  const Graph g = ReadGraphWith(domain, 24, 1, "ros_graph_humble_reader", &status);
  int jazzy_status = -1;
  // Its endpoints are discovered and the graph sample read within the time the first reader needed.
  const Graph as_jazzy = ReadGraphWith(domain, 16, 1, "ros_graph_humble_as_jazzy", &jazzy_status, 5);
  serve->signal(SIGTERM);
  EXPECT_EQ(serve->wait(60s), 0) << test::ReadFile(test::TempPath("ros_graph_humble") + "_serve.log");
  ASSERT_EQ(status, 0) << test::ReadFile(test::TempPath("ros_graph_humble_reader.log"));

  ASSERT_EQ(g.participant.size(), 48u);
  EXPECT_EQ(g.participant.substr(32), std::string(16, '0'));
  ASSERT_EQ(g.nodes.size(), 1u);
  EXPECT_EQ(g.nodes[0].node_namespace, "/");
  EXPECT_EQ(g.nodes[0].name, "estimator");
  const std::map<std::string, std::string> readers = NodeTopics(g, g.nodes[0], 24, false);
  const std::map<std::string, std::string> writers = NodeTopics(g, g.nodes[0], 24, true);
  EXPECT_EQ(readers.size(), 7u);
  EXPECT_TRUE(readers.count("rt/camera/color/image_raw"));
  EXPECT_TRUE(readers.count("rt/camera/color/image_raw/compressed"));
  EXPECT_EQ(writers.size(), 4u);
  EXPECT_TRUE(writers.count("rt/dslam/camera_odometry"));

  EXPECT_EQ(jazzy_status, 1);
  EXPECT_EQ(as_jazzy.participant, g.participant.substr(0, 32));  // decoded, Humble's padding read as no node
  EXPECT_TRUE(as_jazzy.nodes.empty());
}

}  // namespace
}  // namespace dslam
