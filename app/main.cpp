// dslam and dslam-full: the command-line tool (app/command_line.h). The parsing lives in the app library,
// compiled with the commands it calls; dslam hands the commands it does not have to dslam-full
// (app/full_binary.h).
#include <iostream>
#include <string>

#include "app/command_line.h"
#include "app/full_binary.h"
#include "data/frame_memory.h"

int main(int argc, char** argv) {
#ifdef DSLAM_CORE_COMMANDS_ONLY
  if (argc < 2 || !dslam::IsCoreCommand(argv[1])) return dslam::ExecFullBinary(argv, std::cerr);
#endif
  dslam::KeepFrameBuffersInHeap();  // before any thread: frames' buffers are reused, not faulted in again
  return dslam::RunCommandLine(argc, argv);
}
