#include "plugin/fleet_share.h"

#include <algorithm>
#include <stdexcept>

namespace dslam {

FleetShare ParseFleetShare(const std::string& text) {
  const auto bad = [&](const std::string& why) {
    return std::invalid_argument("--fleet-share '" + text + "': " + why + " (expected K/N, this host's place K = 0..N-1 "
                                 "among N serve hosts)");
  };
  const size_t slash = text.find('/');
  if (slash == std::string::npos || slash == 0 || slash + 1 == text.size()) throw bad("no K/N");
  const std::string k = text.substr(0, slash), n = text.substr(slash + 1);
  const auto digits = [](const std::string& s) {
    return s.size() <= 4 && std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
  };
  if (!digits(k) || !digits(n)) throw bad("K and N must be whole numbers");
  FleetShare share{std::stoi(k), std::stoi(n)};
  if (share.hosts < 1 || share.hosts > 1024) throw bad("N must be 1..1024");
  if (share.index >= share.hosts) throw bad("K must be below N");
  return share;
}

std::vector<std::string> VehiclesOfShare(std::vector<std::string> fleet, const FleetShare& share) {
  if (share.hosts < 1 || share.index < 0 || share.index >= share.hosts)
    throw std::invalid_argument("fleet share " + std::to_string(share.index) + "/" + std::to_string(share.hosts) +
                                " is out of range");
  std::sort(fleet.begin(), fleet.end());
  const auto twice = std::adjacent_find(fleet.begin(), fleet.end());
  if (twice != fleet.end()) throw std::invalid_argument("vehicle '" + *twice + "' is named twice in the fleet");
  std::vector<std::string> mine;
  for (size_t i = static_cast<size_t>(share.index); i < fleet.size(); i += static_cast<size_t>(share.hosts))
    mine.push_back(fleet[i]);
  return mine;
}

bool YieldsTo(const std::array<uint8_t, 12>& own_prefix, const std::array<uint8_t, 12>& other_prefix) {
  return other_prefix < own_prefix;
}

}  // namespace dslam
