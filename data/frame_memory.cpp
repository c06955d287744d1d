#include "data/frame_memory.h"

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace dslam {

bool KeepFrameBuffersInHeap() {
#if defined(__GLIBC__)
  constexpr int kLargestHeapBlock = 32 << 20;  // M_MMAP_THRESHOLD's maximum on 64-bit glibc
  constexpr int kKeptFreeTop = 256 << 20;
  return mallopt(M_MMAP_THRESHOLD, kLargestHeapBlock) == 1 && mallopt(M_TRIM_THRESHOLD, kKeptFreeTop) == 1;
#else
  return false;
#endif
}

}  // namespace dslam
