#pragma once
// Whether this host lets a UDP socket have the receive buffer the DDS profile asks for. Over UDP one
// 1242x375 colour image is ~100 fragments sent in one burst; Linux silently caps SO_RCVBUF at
// net.core.rmem_max, and a smaller buffer overflows and loses best-effort samples (a camera driver on
// another host, or another DDS implementation, always comes over UDP).

#include <optional>
#include <string>

namespace dslam {

// The receiveBufferSize of the profile file's UDPv4 transport, in bytes; nothing when it sets none.
std::optional<int> ProfileUdpReceiveBuffer(const std::string& profiles_file);

// Asks the kernel for a UDP socket with `requested_bytes` of receive buffer and reads back what it granted.
// Returns a warning naming both sizes and the fix when it granted less; nothing when it granted enough.
std::optional<std::string> CheckUdpReceiveBuffer(int requested_bytes);

}  // namespace dslam
