#include "data/frame_memory.h"

#include <sys/resource.h>

#include <cstdlib>
#include <cstring>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

namespace dslam {
namespace {

long MinorPageFaults() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_minflt;
}

// What a frame's stages do, 50 frames long: allocate a colour image, a depth map, a pyramid and a grey
// image, write them all, free them. Returns the pages written.
long FramesOfBuffers() {
  constexpr size_t kPage = 4096;
  long pages = 0;
  for (int frame = 0; frame < 50; ++frame) {
    std::vector<char*> buffers;
    for (size_t bytes : {1397250ul, 1863000ul, 3300000ul, 465750ul}) {
      char* p = static_cast<char*>(std::malloc(bytes));
      std::memset(p, frame, bytes);
      buffers.push_back(p);
      pages += static_cast<long>(bytes / kPage);
    }
    for (char* p : buffers) std::free(p);
  }
  return pages;
}

long OnThreeThreads() {
  long pages_a = 0, pages_b = 0;
  std::thread a([&] { pages_a = FramesOfBuffers(); }), b([&] { pages_b = FramesOfBuffers(); });
  const long pages_here = FramesOfBuffers();
  a.join();
  b.join();
  return pages_a + pages_b + pages_here;
}

// glibc's defaults fault on about a third of these pages every time (fresh mappings, trimmed heaps);
// kept in the heaps, the buffers are reused and written without faults once the heaps have grown.
TEST(FrameMemory, FrameSizedBuffersAreReusedWithoutPageFaults) {
#if defined(__GLIBC__)
  ASSERT_TRUE(KeepFrameBuffersInHeap());
  OnThreeThreads();  // the heaps grow to the working set
  const long before = MinorPageFaults();
  const long pages = OnThreeThreads();
  const long faults = MinorPageFaults() - before;
  RecordProperty("faults", static_cast<int>(faults));
  EXPECT_LT(faults, pages / 10) << faults << " page faults over " << pages << " pages written";
#else
  GTEST_SKIP() << "the allocator settings are glibc's";
#endif
}

}  // namespace
}  // namespace dslam
