// Rays waiting inside a unit, ordered by the time they can issue (then by id: deterministic).
// A unit holds a few rays (its capacity), so the queue is a sorted ring: the next ray at the head,
// a ray due later than all others (an operation just issued) appended at the tail, one due before
// all others (a ray just admitted) put before the head, and any other moved in from the tail.
#pragma once

#include "model/sim/time.h"

#include <cstdint>
#include <vector>

namespace rtsim::model {

class ReadyQueue {
 public:
  void push(Tick when, uint32_t ray) {
    if (size_ == buf_.size()) grow();
    const Item x{when, ray};
    const size_t mask = buf_.size() - 1;
    if (size_ > 0 && x.before(buf_[head_])) {
      head_ = (head_ + mask) & mask;
      buf_[head_] = x;
      ++size_;
      return;
    }
    size_t i = size_++;  // the new tail, moved towards the head past every later item
    for (; i > 0 && x.before(buf_[(head_ + i - 1) & mask]); --i)
      buf_[(head_ + i) & mask] = buf_[(head_ + i - 1) & mask];
    buf_[(head_ + i) & mask] = x;
  }
  bool empty() const { return size_ == 0; }
  size_t size() const { return size_; }
  Tick next_time() const { return size_ == 0 ? kUnknown : buf_[head_].when; }
  uint32_t pop() {
    const uint32_t r = buf_[head_].ray;
    head_ = (head_ + 1) & (buf_.size() - 1);
    --size_;
    return r;
  }

 private:
  struct Item {
    Tick when;
    uint32_t ray;
    bool before(const Item& o) const { return when != o.when ? when < o.when : ray < o.ray; }
  };
  void grow() {
    std::vector<Item> bigger(buf_.size() * 2);
    for (size_t i = 0; i < size_; ++i) bigger[i] = buf_[(head_ + i) & (buf_.size() - 1)];
    buf_.swap(bigger);
    head_ = 0;
  }
  std::vector<Item> buf_ = std::vector<Item>(16);  // a power of two
  size_t head_ = 0, size_ = 0;
};

}  // namespace rtsim::model
