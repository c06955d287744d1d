#pragma once
// A fleet spread over several `serve` hosts. Every host is given the same list of vehicles and its place
// among the hosts (`--fleet-share K/N`); host K serves the vehicles at positions K, K + N, ... of the list
// sorted by name. So each vehicle has exactly one host whatever order the lists were written in, and the
// hosts' shares differ by at most one vehicle. A vehicle served twice all the same (two hosts given the
// same share, or the same --vehicle) is caught on the network: serve_node.h, "quiet".

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace dslam {

struct FleetShare {
  int index = 0;  // K, 0-based
  int hosts = 1;  // N
};

// "K/N" with 0 <= K < N <= 1024; throws std::invalid_argument naming what is wrong.
FleetShare ParseFleetShare(const std::string& text);

// The vehicles of `fleet` that host `share.index` of `share.hosts` serves. Throws std::invalid_argument
// for a vehicle named twice in the fleet or a share out of range.
std::vector<std::string> VehiclesOfShare(std::vector<std::string> fleet, const FleetShare& share);

// Two instances publishing one vehicle's estimates where subscribers would take both (shared ownership, or
// exclusive with the same strength): the one whose participant GUID prefix is the lower keeps publishing,
// the other goes quiet. Both see each other, so exactly one yields.
bool YieldsTo(const std::array<uint8_t, 12>& own_prefix, const std::array<uint8_t, 12>& other_prefix);

}  // namespace dslam
