#pragma once
// Transport choices on top of the shipped profiles (config/dds_profiles.xml), for benchmarks and tests
// that must take the network path a camera driver on another host, or another DDS implementation, takes.

#include <string>

namespace dslam {

// The profile file's text without the shared-memory user transport (UDPv4 only). Throws
// std::invalid_argument when the text lists no `dslam_shm` user transport.
std::string WithoutSharedMemoryTransport(const std::string& profiles_xml);

// Participants of this process exchange data through their transports from now on, instead of Fast
// DDS' intra-process shortcut (which is on by default and bypasses every transport). Call before any
// participant exists.
void DisableIntraprocessDelivery();

}  // namespace dslam
