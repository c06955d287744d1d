#pragma once
// An output folder taken by one process at a time: a second `dslam serve` (or anything else using it)
// writing the same folder gets an error naming it instead of interleaving its files with the first's.
// An advisory lock (flock) on DIR/.dslam.lock, released when the holder exits, however it exits.

#include <string>

namespace dslam {

class DirLock {
 public:
  // Creates `dir` if needed and takes it; throws std::runtime_error naming it (and the holder's pid)
  // when another process has it, or when it cannot be created.
  explicit DirLock(const std::string& dir);
  ~DirLock();
  DirLock(const DirLock&) = delete;
  DirLock& operator=(const DirLock&) = delete;

 private:
  int fd_ = -1;
};

}  // namespace dslam
