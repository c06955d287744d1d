#include "render/headless_display.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <sstream>
#include <thread>

namespace dslam {

std::string FindOnPath(const std::string& program) {
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path ? path : "/usr/bin:/bin");
  std::string dir;
  while (std::getline(dirs, dir, ':')) {
    const std::string candidate = (dir.empty() ? "." : dir) + "/" + program;
    if (::access(candidate.c_str(), X_OK) == 0) return candidate;
  }
  return {};
}

std::optional<HeadlessDisplay> HeadlessDisplay::Acquire(std::string* error) {
  const char* existing = std::getenv("DISPLAY");
  if (existing && *existing) return HeadlessDisplay(-1, existing);

  const std::string xvfb = FindOnPath("Xvfb");
  if (xvfb.empty()) {
    *error = "no X display (DISPLAY is unset) and Xvfb is not installed: install it with 'apt-get install xvfb'";
    return std::nullopt;
  }
  // A free display number: no lock file. Another process may race us to it; Xvfb then exits and we
  // try the next one.
  for (int n = 90 + static_cast<int>(::getpid() % 50); n < 400; ++n) {
    const std::string lock = "/tmp/.X" + std::to_string(n) + "-lock";
    if (::access(lock.c_str(), F_OK) == 0) continue;
    const std::string display = ":" + std::to_string(n);
    const pid_t parent = ::getpid();
    const pid_t pid = ::fork();
    if (pid < 0) break;
    if (pid == 0) {
      // Xvfb must never outlive us, however we end (SIGTERM while drawing, a crash, SIGKILL): the kernel
      // sends it SIGTERM when we die. Had we died already, before this call, its parent is another one.
      ::prctl(PR_SET_PDEATHSIG, SIGTERM);
      if (::getppid() != parent) ::_exit(0);
      const int devnull = ::open("/dev/null", O_RDWR);
      if (devnull >= 0) {
        ::dup2(devnull, STDIN_FILENO);
        ::dup2(devnull, STDOUT_FILENO);
        ::dup2(devnull, STDERR_FILENO);
      }
      ::execl(xvfb.c_str(), "Xvfb", display.c_str(), "-screen", "0", "4096x4096x24", "-nolisten", "tcp",
              static_cast<char*>(nullptr));
      ::_exit(127);
    }
    const std::string socket = "/tmp/.X11-unix/X" + std::to_string(n);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    bool exited = false;
    while (std::chrono::steady_clock::now() < deadline) {
      int status = 0;
      if (::waitpid(pid, &status, WNOHANG) == pid) {
        exited = true;
        break;
      }
      if (::access(socket.c_str(), F_OK) == 0) {
        ::setenv("DISPLAY", display.c_str(), 1);
        return HeadlessDisplay(pid, display);
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    if (!exited) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, nullptr, 0);
    }
  }
  *error = "could not start Xvfb (" + xvfb + ") on any free display";
  return std::nullopt;
}

HeadlessDisplay::HeadlessDisplay(HeadlessDisplay&& other) noexcept : pid_(other.pid_), display_(std::move(other.display_)) {
  other.pid_ = -1;
}

HeadlessDisplay::~HeadlessDisplay() {
  if (pid_ <= 0) return;
  ::kill(pid_, SIGTERM);
  ::waitpid(pid_, nullptr, 0);
  ::unsetenv("DISPLAY");
}

}  // namespace dslam
