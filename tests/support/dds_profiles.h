#pragma once
// Fast DDS profiles for the multi-process tests, which compare every frame and so cannot lose one.

#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "plugin/transport_profiles.h"
#include "support/child_process.h"

namespace dslam::test {

// The text of the `<tag profile_name="name"> ... </tag>` element in `xml`, as [begin, end) offsets;
// {npos, npos} when it is missing.
inline std::pair<size_t, size_t> ProfileElement(const std::string& xml, const std::string& tag,
                                                const std::string& name) {
  const size_t begin = xml.find("<" + tag + " profile_name=\"" + name + "\"");
  if (begin == std::string::npos) return {std::string::npos, std::string::npos};
  const size_t end = xml.find("</" + tag + ">", begin);
  return {begin, end};
}

// Writes `profiles_in` to `profiles_out` with lossless sensor streams and returns `profiles_out`:
//  - the sensor reader is reliable instead of best-effort: on a loaded machine best-effort loses a
//    sample now and then;
//  - it is transient-local instead of volatile, and both the sensor writer and reader keep all samples
//    instead of the last 5: discovery is not symmetric, and a publisher that has matched serve's reader
//    writes samples that reader drops until it has matched the writer too (a restarted publisher hits
//    this, and so does secure discovery). The reader then asks for them again at the writer's next
//    heartbeat, up to 3 s later, so the writer must still have them (at 5 Hz the last 5 are gone after
//    1 s), and they arrive in one burst, of which a keep-last 5 reader history would keep the last 5.
inline std::string WithLosslessSensorStreams(const std::string& profiles_in, const std::string& profiles_out) {
  std::string xml = ReadFile(profiles_in);
  auto replace_in = [&](std::pair<size_t, size_t> element, const std::string& from, const std::string& to) {
    const size_t at = xml.find(from, element.first);
    const bool found = at != std::string::npos && at < element.second;
    EXPECT_TRUE(found) << profiles_in << ": expected " << from << " in a sensor profile";
    if (found) xml.replace(at, from.size(), to);
  };
  replace_in(ProfileElement(xml, "data_reader", "sensor_reader"), "<kind>BEST_EFFORT</kind>", "<kind>RELIABLE</kind>");
  replace_in(ProfileElement(xml, "data_reader", "sensor_reader"), "</reliability>",
             "</reliability><durability><kind>TRANSIENT_LOCAL</kind></durability>");
  replace_in(ProfileElement(xml, "data_reader", "sensor_reader"), "<kind>KEEP_LAST</kind>", "<kind>KEEP_ALL</kind>");
  replace_in(ProfileElement(xml, "data_writer", "sensor_writer"), "<kind>KEEP_LAST</kind>", "<kind>KEEP_ALL</kind>");
  std::ofstream(profiles_out) << xml;
  return profiles_out;
}

// Writes `profiles_in` to `profiles_out` without the shared-memory transport (UDPv4 only), as a participant
// on another host or another DDS implementation talks to serve, and returns `profiles_out`.
inline std::string WithoutSharedMemory(const std::string& profiles_in, const std::string& profiles_out) {
  std::ofstream(profiles_out) << WithoutSharedMemoryTransport(ReadFile(profiles_in));
  return profiles_out;
}

}  // namespace dslam::test
