#include "pipeline/bounded_queue.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>
#include <vector>

namespace dslam {
namespace {
using namespace std::chrono_literals;

TEST(BoundedQueue, PushWaitsForRoomAndItemsLeaveInOrder) {
  BoundedQueue<int> queue(2);
  ASSERT_TRUE(queue.push(1));
  ASSERT_TRUE(queue.push(2));
  std::atomic<bool> third_in{false};
  std::thread producer([&] {
    queue.push(3);  // full: waits for the consumer
    third_in = true;
  });
  std::this_thread::sleep_for(100ms);
  EXPECT_FALSE(third_in);
  EXPECT_EQ(queue.size(), 2u);
  EXPECT_EQ(queue.pop(), 1);
  producer.join();
  EXPECT_TRUE(third_in);
  EXPECT_EQ(queue.pop(), 2);
  EXPECT_EQ(queue.pop(), 3);
  EXPECT_EQ(queue.dropped(), 0u);
}

TEST(BoundedQueue, PushDropOldestNeverWaitsAndCountsWhatItDropped) {
  BoundedQueue<int> queue(3);
  for (int i = 0; i < 10; ++i) EXPECT_TRUE(queue.pushDropOldest(i));
  EXPECT_EQ(queue.size(), 3u);
  EXPECT_EQ(queue.dropped(), 7u);
  EXPECT_EQ(queue.pop(), 7);
  EXPECT_EQ(queue.pop(), 8);
  EXPECT_EQ(queue.pop(), 9);
}

TEST(BoundedQueue, ADroppedItemHandsWhatTheNextNeedsOnToIt) {
  // As a dropped frame's odometry goes into the next frame's: here each item carries a sum on.
  BoundedQueue<int> queue(2);
  auto carry = [](const int& dropped, int& next) { next += dropped; };
  for (int i = 1; i <= 5; ++i) EXPECT_TRUE(queue.pushDropOldest(i, carry));
  EXPECT_EQ(queue.dropped(), 3u);
  EXPECT_EQ(queue.pop(), 1 + 2 + 3 + 4);  // 1 into 2, (1+2) into 3, (1+2+3) into 4
  EXPECT_EQ(queue.pop(), 5);
  BoundedQueue<int> one(1);  // capacity 1: the dropped item's successor is the new one
  EXPECT_TRUE(one.pushDropOldest(10, carry));
  EXPECT_TRUE(one.pushDropOldest(1, carry));
  EXPECT_EQ(one.pop(), 11);
}

TEST(BoundedQueue, CloseDrainsThenEndsAndReleasesWaitingThreads) {
  BoundedQueue<int> queue(1);
  queue.push(1);
  std::thread blocked_producer([&] { EXPECT_FALSE(queue.push(2)); });
  std::this_thread::sleep_for(50ms);
  queue.close();
  blocked_producer.join();
  EXPECT_FALSE(queue.push(3));
  EXPECT_FALSE(queue.pushDropOldest(4));
  EXPECT_EQ(queue.pop(), 1);  // what was queued before close still comes out
  EXPECT_EQ(queue.pop(), std::nullopt);

  BoundedQueue<int> empty(1);
  std::thread blocked_consumer([&] { EXPECT_EQ(empty.pop(), std::nullopt); });
  std::this_thread::sleep_for(50ms);
  empty.close();
  blocked_consumer.join();
  EXPECT_THROW(BoundedQueue<int>(0), std::invalid_argument);
}

}  // namespace
}  // namespace dslam
