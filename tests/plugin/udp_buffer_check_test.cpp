#include "plugin/udp_buffer_check.h"

#include <gtest/gtest.h>

#include <fstream>

#include "support/temp_paths.h"

namespace dslam {
namespace {

int RmemMax() {
  std::ifstream in("/proc/sys/net/core/rmem_max");
  int v = 0;
  in >> v;
  return v;
}

TEST(UdpBufferCheck, TheShippedProfileAsksFor4MiB) {
  EXPECT_EQ(ProfileUdpReceiveBuffer(std::string(DSLAM_SOURCE_DIR) + "/config/dds_profiles.xml"), 4194304);
  const std::string bare = test::TempPath("bare_profiles.xml");
  std::ofstream(bare) << "<transport_descriptor><type>UDPv4</type></transport_descriptor>";
  EXPECT_EQ(ProfileUdpReceiveBuffer(bare), std::nullopt);
}

TEST(UdpBufferCheck, WarnsWithTheFixWhenTheKernelGrantsLess) {
  const int rmem_max = RmemMax();
  ASSERT_GT(rmem_max, 0);
  EXPECT_EQ(CheckUdpReceiveBuffer(rmem_max / 2), std::nullopt);  // within the limit: granted
  const auto warning = CheckUdpReceiveBuffer(2 * rmem_max);    // beyond it: capped
  ASSERT_TRUE(warning.has_value());
  EXPECT_NE(warning->find("net.core.rmem_max=" + std::to_string(2 * rmem_max)), std::string::npos) << *warning;
}

}  // namespace
}  // namespace dslam
