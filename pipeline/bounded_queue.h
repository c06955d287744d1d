#pragma once
// A bounded FIFO between two pipeline stages (one producer thread, one consumer thread, or more). It
// never grows past its capacity:
//  - push() waits for room: back-pressure, for stages whose packets depend on their predecessors and so
//    cannot be dropped (a frame's measurement refers to the previous frame's tracks and pose);
//  - pushDropOldest() never waits: when full it drops the oldest item and counts it, for a producer that
//    must not block (a DDS receive thread).
// close() wakes everyone: pushes then fail, pops drain what is left and then return nothing.

#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <mutex>
#include <optional>
#include <stdexcept>

namespace dslam {

template <class T>
class BoundedQueue {
 public:
  explicit BoundedQueue(size_t capacity) : capacity_(capacity) {
    if (capacity_ == 0) throw std::invalid_argument("a bounded queue needs a capacity of at least 1");
  }

  // Waits while the queue is full; false (the item is not queued) once the queue is closed.
  bool push(T item) {
    std::unique_lock<std::mutex> lock(mutex_);
    not_full_.wait(lock, [&] { return closed_ || items_.size() < capacity_; });
    if (closed_) return false;
    items_.push_back(std::move(item));
    not_empty_.notify_one();
    return true;
  }

  // Never waits; drops (and counts) the oldest item when full. False once the queue is closed.
  bool pushDropOldest(T item) {
    return pushDropOldest(std::move(item), [](const T&, T&) {});
  }
  // The same, handing the dropped item and the one that now comes first after it to carry(dropped, next)
  // before it goes, so that what the next one needs of it survives (a dropped frame's odometry composed
  // into the next frame's).
  template <class Carry>
  bool pushDropOldest(T item, Carry carry) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (closed_) return false;
    if (items_.size() >= capacity_) {
      T dropped = std::move(items_.front());
      items_.pop_front();
      ++dropped_;
      carry(static_cast<const T&>(dropped), items_.empty() ? item : items_.front());
    }
    items_.push_back(std::move(item));
    not_empty_.notify_one();
    return true;
  }

  // Waits for an item; nothing once the queue is closed and empty.
  std::optional<T> pop() {
    std::unique_lock<std::mutex> lock(mutex_);
    not_empty_.wait(lock, [&] { return closed_ || !items_.empty(); });
    if (items_.empty()) return std::nullopt;
    T item = std::move(items_.front());
    items_.pop_front();
    not_full_.notify_one();
    return item;
  }

  void close() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      closed_ = true;
    }
    not_full_.notify_all();
    not_empty_.notify_all();
  }

  size_t size() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return items_.size();
  }
  uint64_t dropped() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return dropped_;
  }

 private:
  const size_t capacity_;
  mutable std::mutex mutex_;
  std::condition_variable not_full_, not_empty_;
  std::deque<T> items_;
  bool closed_ = false;
  uint64_t dropped_ = 0;
};

}  // namespace dslam
