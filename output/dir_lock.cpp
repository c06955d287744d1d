#include "output/dir_lock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <stdexcept>

namespace dslam {
namespace {

std::string LockPath(const std::string& dir) { return dir + "/.dslam.lock"; }

// What the holder of the lock on `fd` wrote when it took it: its pid ("" when nothing could be read).
std::string HolderWritten(int fd) {
  char holder[32] = {0};
  const ssize_t n = ::pread(fd, holder, sizeof holder - 1, 0);
  return n > 0 ? std::string(holder, static_cast<size_t>(n)) : std::string();
}

}  // namespace

DirLock::DirLock(const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw std::runtime_error("cannot create the output folder " + dir + ": " + ec.message());
  fd_ = ::open(LockPath(dir).c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) throw std::runtime_error("cannot write in the output folder " + dir + ": " + std::strerror(errno));
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    const std::string holder = HolderWritten(fd_);
    ::close(fd_);
    fd_ = -1;
    throw FolderInUseError("output folder " + dir + " is in use by another process" +
                             (holder.empty() ? std::string() : " (pid " + holder + ")") +
                             ": give each its own --out or vehicle name");
  }
  const std::string pid = std::to_string(::getpid());
  if (::ftruncate(fd_, 0) == 0) {
    const ssize_t written = ::pwrite(fd_, pid.data(), pid.size(), 0);
    (void)written;  // the pid is a courtesy for the error message; the lock is what matters
  }
}

long FolderHolderPid(const std::string& dir) {
  const int fd = ::open(LockPath(dir).c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return 0;
  long pid = 0;
  if (::flock(fd, LOCK_SH | LOCK_NB) != 0)  // held: the holder wrote its pid when it took the lock
    pid = std::strtol(HolderWritten(fd).c_str(), nullptr, 10);
  ::close(fd);  // releases the shared lock if it was taken
  return pid;
}

DirLock::~DirLock() {
  if (fd_ >= 0) ::close(fd_);  // releases the lock
}

}  // namespace dslam
