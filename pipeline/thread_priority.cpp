#include "pipeline/thread_priority.h"

#include <algorithm>
#include <cerrno>

#if defined(__linux__)
#include <sys/resource.h>
#include <unistd.h>
#endif

namespace dslam {

int ThisThreadsNice() {
#if defined(__linux__)
  errno = 0;
  const int nice = getpriority(PRIO_PROCESS, static_cast<id_t>(gettid()));  // -1 is also a valid value
  return errno == 0 ? nice : 0;
#else
  return 0;
#endif
}

bool LowerThisThreadsPriority(int steps) {
#if defined(__linux__)
  if (steps <= 0) return steps == 0;
  return setpriority(PRIO_PROCESS, static_cast<id_t>(gettid()), std::min(19, ThisThreadsNice() + steps)) == 0;
#else
  (void)steps;
  return false;
#endif
}

}  // namespace dslam
