#include "plugin/udp_buffer_check.h"

#include <sys/socket.h>
#include <unistd.h>

#include <fstream>
#include <regex>
#include <sstream>

namespace dslam {

std::optional<int> ProfileUdpReceiveBuffer(const std::string& profiles_file) {
  std::ifstream in(profiles_file);
  std::stringstream text;
  text << in.rdbuf();
  const std::string xml = text.str();
  const size_t udp = xml.find("<type>UDPv4</type>");
  if (udp == std::string::npos) return std::nullopt;
  const size_t end = xml.find("</transport_descriptor>", udp);
  std::smatch match;
  const std::string descriptor = xml.substr(udp, end == std::string::npos ? std::string::npos : end - udp);
  if (!std::regex_search(descriptor, match, std::regex("<receiveBufferSize>\\s*([0-9]+)\\s*</receiveBufferSize>")))
    return std::nullopt;
  return std::stoi(match[1].str());
}

std::optional<std::string> CheckUdpReceiveBuffer(int requested_bytes) {
  const int fd = socket(AF_INET, SOCK_DGRAM, 0);
  if (fd < 0) return "cannot open a UDP socket to check its receive buffer";
  setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &requested_bytes, sizeof requested_bytes);
  int granted = 0;
  socklen_t length = sizeof granted;
  getsockopt(fd, SOL_SOCKET, SO_RCVBUF, &granted, &length);
  close(fd);
  granted /= 2;  // Linux reports twice the size it grants (the other half is its bookkeeping)
  if (granted >= requested_bytes) return std::nullopt;
  return "the kernel grants UDP sockets " + std::to_string(granted) + " bytes of receive buffer, the DDS profile asks for " +
         std::to_string(requested_bytes) + ": images over UDP (another host, another DDS implementation) will lose "
         "fragments; on this host run: sysctl -w net.core.rmem_max=" + std::to_string(requested_bytes) +
         " (docs/serve.md, QoS and the vehicle network)";
}

}  // namespace dslam
