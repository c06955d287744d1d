#include "app/full_binary.h"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <iostream>

extern char** environ;

namespace dslam {
namespace {

namespace fs = std::filesystem;

constexpr const char* kFullName = "dslam-full";

}  // namespace

bool IsCoreCommand(const std::string& command) {
  static const std::array<const char*, 4> kCore = {"run", "sim", "kitti-replay", "lidar-check"};
  for (const char* c : kCore)
    if (command == c) return true;
  return false;
}

std::string FullBinaryPath() {
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const fs::path beside = self.parent_path() / kFullName;
    if (fs::exists(beside, ec)) return beside.string();
  }
#ifdef DSLAM_FULL_BINARY
  if (fs::exists(DSLAM_FULL_BINARY, ec)) return DSLAM_FULL_BINARY;
#endif
  return {};
}

int ExecFullBinary(char** argv, std::ostream& err) {
  const std::string full = FullBinaryPath();
  if (full.empty()) {
    err << "dslam: error: " << kFullName << " (the commands that need VTK or Fast DDS) is not beside dslam: build "
        << "it (cmake --build build)" << std::endl;
    return 2;
  }
  std::cout.flush();
  ::execv(full.c_str(), argv);  // argv[0] kept: usage lines say what the user typed
  err << "dslam: error: cannot start " << full << ": " << std::strerror(errno) << std::endl;
  return 2;
}

int RunFullBinary(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
  const std::string full = FullBinaryPath();
  if (full.empty()) {
    err << "dslam: error: " << kFullName << ", which draws the figures, is not beside dslam: build it (cmake "
        << "--build build), or pass --no-figures" << std::endl;
    return 2;
  }
  std::vector<char*> child_argv{const_cast<char*>(full.c_str())};
  for (const std::string& a : args) child_argv.push_back(const_cast<char*>(a.c_str()));
  child_argv.push_back(nullptr);
  out.flush();
  err.flush();
  std::cout.flush();
  std::cerr.flush();
  pid_t pid = 0;
  if (const int e = ::posix_spawn(&pid, full.c_str(), nullptr, nullptr, child_argv.data(), environ); e != 0) {
    err << "dslam: error: cannot start " << full << ": " << std::strerror(e) << std::endl;
    return 2;
  }
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) {
      err << "dslam: error: lost " << full << ": " << std::strerror(errno) << std::endl;
      return 2;
    }
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  err << "dslam: error: " << full << " (drawing the figures) died of signal " << WTERMSIG(status) << std::endl;
  return 2;
}

}  // namespace dslam
