#pragma once
// Unique scratch paths for tests (per process, so parallel ctest runs never collide).

#include <unistd.h>

#include <filesystem>
#include <string>

namespace dslam::test {

inline std::string TempPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("dslam_test_" + std::to_string(::getpid()) + "_" + name)).string();
}

// Like TempPath, and creates the directory.
inline std::string TempDir(const std::string& name) {
  const std::string dir = TempPath(name);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace dslam::test
