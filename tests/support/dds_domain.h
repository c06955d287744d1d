#pragma once
// Domain ids for the multi-process DDS tests.

#include <filesystem>
#include <functional>
#include <string>

namespace dslam::test {

// Slots of the tests that start DDS participants, one each: tests that ctest runs at the same time
// never share a domain. (Ids derived from the pid did: two concurrent tests' ids met about once in 50.)
enum class DdsTestSlot { kLoopbackEqual = 0, kLoopbackBadSamples, kLoopbackRestart, kLoopbackTwoProcesses, kSecurity,
                         kLoopbackSigkill, kServeNodeErrors, kPublishStop, kLoopbackSecondSignal, kLoopbackSamplesLost,
                         kCycloneListener, kCycloneCameraDriver, kCycloneImageReader, kRosGraphJazzy, kRosGraphHumble,
                         kLoopbackNewestWins, kServeLidar, kLoopbackQuiet, kPublishTwist, kSlots };
static_assert(static_cast<int>(DdsTestSlot::kSlots) <= 32, "32 domain ids per build tree");

// The slot's domain id: the base (0, 32, ..., 192; domain ids go up to 232) comes from the test binary's
// directory, so that the suites of two build trees run at once on one host collide only 1 time in 7.
inline int DomainFor(DdsTestSlot slot) {
  std::error_code ec;
  const std::string build_dir = std::filesystem::read_symlink("/proc/self/exe", ec).parent_path().string();
  return static_cast<int>(std::hash<std::string>{}(build_dir) % 7) * 32 + static_cast<int>(slot);
}

}  // namespace dslam::test
