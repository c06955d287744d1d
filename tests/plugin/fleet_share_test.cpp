#include "plugin/fleet_share.h"

#include <algorithm>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace dslam {
namespace {

TEST(FleetShare, EveryVehicleHasExactlyOneHostAndTheSharesDifferByAtMostOne) {
  const std::vector<std::string> fleet = {"v3", "v0", "truck/a", "v1", "v2", "bus", "v10"};
  for (int hosts = 1; hosts <= 9; ++hosts) {
    std::map<std::string, int> hosts_of;
    size_t smallest = fleet.size(), largest = 0;
    for (int k = 0; k < hosts; ++k) {
      const std::vector<std::string> mine = VehiclesOfShare(fleet, FleetShare{k, hosts});
      for (const std::string& v : mine) ++hosts_of[v];
      smallest = std::min(smallest, mine.size()), largest = std::max(largest, mine.size());
    }
    EXPECT_EQ(hosts_of.size(), fleet.size()) << hosts << " hosts";
    for (const auto& [vehicle, count] : hosts_of) EXPECT_EQ(count, 1) << vehicle << " with " << hosts << " hosts";
    EXPECT_LE(largest - smallest, 1u) << hosts << " hosts";
  }
}

TEST(FleetShare, TheShareDoesNotDependOnTheOrderTheListWasWrittenIn) {
  std::vector<std::string> fleet = {"a", "b", "c", "d", "e"};
  const std::vector<std::string> first = VehiclesOfShare(fleet, FleetShare{1, 2});
  EXPECT_EQ(first, (std::vector<std::string>{"b", "d"}));
  std::reverse(fleet.begin(), fleet.end());
  EXPECT_EQ(VehiclesOfShare(fleet, FleetShare{1, 2}), first);
  std::rotate(fleet.begin(), fleet.begin() + 2, fleet.end());
  EXPECT_EQ(VehiclesOfShare(fleet, FleetShare{1, 2}), first);
}

TEST(FleetShare, ParsesKOfNAndRefusesWhatIsNotAPlaceAmongTheHosts) {
  const FleetShare share = ParseFleetShare("2/3");
  EXPECT_EQ(share.index, 2);
  EXPECT_EQ(share.hosts, 3);
  for (const char* bad : {"", "3", "3/3", "1/0", "-1/2", "a/2", "1/b", "/2", "1/", "1/2/3", "1/99999"}) {
    try {
      ParseFleetShare(bad);
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("--fleet-share '" + std::string(bad) + "'"), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(VehiclesOfShare({"a", "b", "a"}, FleetShare{0, 2}), std::invalid_argument);
  EXPECT_THROW(VehiclesOfShare({"a"}, FleetShare{2, 2}), std::invalid_argument);
}

TEST(FleetShare, OfTwoInstancesPublishingOneVehicleExactlyOneYields) {
  std::array<uint8_t, 12> a{}, b{};
  a[4] = 1, b[4] = 2;
  EXPECT_TRUE(YieldsTo(b, a) != YieldsTo(a, b));
  EXPECT_TRUE(YieldsTo(b, a));
  EXPECT_FALSE(YieldsTo(a, a));
}

}  // namespace
}  // namespace dslam
