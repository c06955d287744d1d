#pragma once
// Unique scratch paths for tests (per process, so parallel ctest runs never collide), removed when the
// test process exits (a rendered city is 140 MB) unless DSLAM_KEEP_TEST_FILES is set in the environment.

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

namespace dslam::test {

inline std::string ScratchPrefix() { return "dslam_test_" + std::to_string(::getpid()) + "_"; }

inline std::string TempPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() / (ScratchPrefix() + name)).string();
}

// One per test binary: at exit, removes every scratch path this process made.
struct ScratchCleanup {
  ~ScratchCleanup() {
    if (std::getenv("DSLAM_KEEP_TEST_FILES")) return;
    // No exception may leave a destructor that runs at exit: every call takes an error code.
    std::error_code ec;
    const std::filesystem::path tmp = std::filesystem::temp_directory_path(ec);
    if (ec) return;
    const std::string prefix = ScratchPrefix();
    std::vector<std::filesystem::path> mine;
    for (std::filesystem::directory_iterator it(tmp, ec), end; !ec && it != end; it.increment(ec))
      if (it->path().filename().string().rfind(prefix, 0) == 0) mine.push_back(it->path());
    for (const auto& path : mine) std::filesystem::remove_all(path, ec);
  }
};
inline ScratchCleanup scratch_cleanup;

// Like TempPath, and creates the directory.
inline std::string TempDir(const std::string& name) {
  const std::string dir = TempPath(name);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace dslam::test
