// dslam: the command-line tool (app/command_line.h). The parsing lives in the app library, compiled with the
// commands it calls.
#include "app/command_line.h"
#include "data/frame_memory.h"

int main(int argc, char** argv) {
  dslam::KeepFrameBuffersInHeap();  // before any thread: frames' buffers are reused, not faulted in again
  return dslam::RunCommandLine(argc, argv);
}
