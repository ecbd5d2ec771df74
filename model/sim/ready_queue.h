// Rays waiting inside a unit, ordered by the time they can issue (then by id: deterministic).
// A unit holds a few rays (its capacity), so the queue is a sorted ring: the next ray at the head,
// a ray due later than all others (an operation just issued) appended at the tail, one due before
// all others (a ray just admitted) put before the head, and any other moved in from the tail.
#pragma once

#include "model/sim/ring.h"
#include "model/sim/time.h"

#include <cstdint>

namespace rtsim::model {

class ReadyQueue {
 public:
  [[gnu::always_inline]] void push(Tick when, uint32_t ray) {
    const Item x{when, ray};
    // Most pushes are an operation that just issued: due after every ray already waiting.
    if (q_.empty() || (!q_.full() && !x.before(q_.back()))) {
      q_.push_back(x);
      return;
    }
    insert(x);
  }
  bool empty() const { return q_.empty(); }
  size_t size() const { return q_.size(); }
  Tick next_time() const { return q_.empty() ? kUnknown : q_.front().when; }
  uint32_t pop() {
    const uint32_t r = q_.front().ray;
    q_.pop_front();
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
    if (x.before(q_.front())) {
      q_.push_front(x);
      return;
    }
    q_.insert_from_back(x, [](const Item& a, const Item& b) { return a.before(b); });
  }
  Ring<Item> q_;
};

}  // namespace rtsim::model
