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
  [[gnu::always_inline]] void push(Tick when, uint32_t ray) {
    const Item x{when, ray};
    // Most pushes are an operation that just issued: due after every ray already waiting.
    if (size_ == 0 || (size_ <= mask_ && !x.before(buf_[(head_ + size_ - 1) & mask_]))) {
      buf_[(head_ + size_++) & mask_] = x;
      return;
    }
    insert(x);
  }
  bool empty() const { return size_ == 0; }
  size_t size() const { return size_; }
  Tick next_time() const { return size_ == 0 ? kUnknown : buf_[head_].when; }
  uint32_t pop() {
    const uint32_t r = buf_[head_].ray;
    head_ = (head_ + 1) & mask_;
    --size_;
    return r;
  }

 private:
  struct Item {
    Tick when;
    uint32_t ray;
    bool before(const Item& o) const { return when != o.when ? when < o.when : ray < o.ray; }
  };
  // push() of an item due before the tail, or into a full ring.
  [[gnu::noinline]] void insert(const Item& x) {
    if (size_ > mask_) grow();
    if (x.before(buf_[head_])) {
      head_ = (head_ + mask_) & mask_;
      buf_[head_] = x;
      ++size_;
      return;
    }
    size_t i = size_++;  // the new tail, moved towards the head past every later item
    for (; i > 0 && x.before(buf_[(head_ + i - 1) & mask_]); --i)
      buf_[(head_ + i) & mask_] = buf_[(head_ + i - 1) & mask_];
    buf_[(head_ + i) & mask_] = x;
  }
  void grow() {
    std::vector<Item> bigger(buf_.size() * 2);
    for (size_t i = 0; i < size_; ++i) bigger[i] = buf_[(head_ + i) & mask_];
    buf_.swap(bigger);
    mask_ = buf_.size() - 1;
    head_ = 0;
  }
  std::vector<Item> buf_ = std::vector<Item>(16);  // a power of two
  size_t mask_ = 15;                               // buf_.size() - 1
  size_t head_ = 0, size_ = 0;
};

}  // namespace rtsim::model
