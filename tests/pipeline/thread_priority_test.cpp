// A thread lowers its own priority and no other thread's.
#include "pipeline/thread_priority.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <thread>

namespace dslam {
namespace {

TEST(ThreadPriority, AThreadLowersItsOwnPriorityOnly) {
  const int main_before = ThisThreadsNice();
  int before = 0, after = 0, capped = 0;
  bool lowered = false, zero = false, negative = true;
  std::thread worker([&] {
    before = ThisThreadsNice();
    lowered = LowerThisThreadsPriority(3);
    after = ThisThreadsNice();
    zero = LowerThisThreadsPriority(0);
    negative = LowerThisThreadsPriority(-1);  // raising it back is not this function's to do
    LowerThisThreadsPriority(100);
    capped = ThisThreadsNice();
  });
  worker.join();
  EXPECT_EQ(before, main_before);  // a new thread starts at its creator's priority
  ASSERT_TRUE(lowered);
  EXPECT_EQ(after, std::min(19, before + 3));
  EXPECT_TRUE(zero);
  EXPECT_FALSE(negative);
  EXPECT_EQ(capped, 19);
  EXPECT_EQ(ThisThreadsNice(), main_before);
}

}  // namespace
}  // namespace dslam
