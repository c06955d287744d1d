#pragma once
// dslam is two executables. `dslam` runs the commands that need neither VTK nor Fast DDS (run, sim,
// kitti-replay, lidar-check) and hands every other command line to `dslam-full`, which has them all: mapping
// VTK, MPI and Fast DDS (about 70 of dslam-full's 120 shared libraries) costs a process ~50 ms at start-up, a
// fortieth of a 60-frame run. The figures at the end of a run are drawn by `dslam-full figures` as a child.

#include <ostream>
#include <string>
#include <vector>

namespace dslam {

// Whether `dslam` runs this command itself (the others go to dslam-full).
bool IsCoreCommand(const std::string& command);

// dslam-full: beside the running executable, else in the build tree this one was built in (test binaries).
// Empty when neither exists.
std::string FullBinaryPath();

// Replaces this process by dslam-full with the same arguments; returns only on failure (exit status 2, the
// reason on err).
int ExecFullBinary(char** argv, std::ostream& err);

// Runs dslam-full with `args` as a child on this process's standard streams (flushed first); returns its exit
// status (2 when it cannot start or dies, the reason on err).
int RunFullBinary(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);

}  // namespace dslam
