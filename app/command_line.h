#pragma once
// The dslam command line: parses the arguments and runs the subcommand they name (each in its own file).
// Returns the process's exit status (the table in the README's "Exit status"). Compiled twice: into dslam-full
// with every command, and into dslam (DSLAM_CORE_COMMANDS_ONLY) with those of app/full_binary.h.

namespace dslam {

int RunCommandLine(int argc, char** argv);

}  // namespace dslam
