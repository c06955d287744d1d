// dslam: the command-line tool (app/command_line.h). The parsing lives in the app library, compiled with the
// commands it calls.
#include "app/command_line.h"

int main(int argc, char** argv) { return dslam::RunCommandLine(argc, argv); }
