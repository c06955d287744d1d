#pragma once
// An output folder taken by one process at a time: a second dslam command writing the same folder gets an
// error naming it instead of interleaving its files with the first's.
// An advisory lock (flock) on DIR/.dslam.lock, released when the holder exits, however it exits.

#include <stdexcept>
#include <string>

namespace dslam {

// Another process holds the folder (exit status 4 at the command line; anything else about the folder is bad
// input, status 2).
class FolderInUseError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The pid of the process holding `dir` (as it wrote it), 0 when none does. A run's figures are drawn by a child
// process (app/full_binary.h) into the folder its parent holds: it asks this rather than taking the folder.
long FolderHolderPid(const std::string& dir);

class DirLock {
 public:
  // Creates `dir` if needed and takes it; throws FolderInUseError naming it (and the holder's pid) when
  // another process has it, std::runtime_error when it cannot be created or written.
  explicit DirLock(const std::string& dir);
  ~DirLock();
  DirLock(const DirLock&) = delete;
  DirLock& operator=(const DirLock&) = delete;

 private:
  int fd_ = -1;
};

}  // namespace dslam
