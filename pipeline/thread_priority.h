#pragma once
// A thread's scheduling priority among the process's threads (its nice value; Linux sets it per thread).
// A thread may lower its own priority, never raise it back: an unprivileged process cannot.

namespace dslam {

// Lowers the calling thread's priority by `steps` nice levels (at most to 19). False where that is not
// possible (another system, or the call refused); the thread then runs as before.
bool LowerThisThreadsPriority(int steps);

// The calling thread's nice value (0 where unknown).
int ThisThreadsNice();

}  // namespace dslam
