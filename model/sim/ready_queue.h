// Rays waiting inside a unit, ordered by the time they can issue (then by id: deterministic).
// A unit holds a few rays (its capacity), so the queue is a vector sorted latest first: the next
// ray is at the back, and a new one, usually due soon, is moved in from the back.
#pragma once

#include "model/sim/time.h"

#include <cstdint>
#include <vector>

namespace rtsim::model {

class ReadyQueue {
 public:
  void push(Tick when, uint32_t ray) {
    const Item x{when, ray};
    size_t i = items_.size();
    items_.push_back(x);
    for (; i > 0 && items_[i - 1].before(x); --i) items_[i] = items_[i - 1];
    items_[i] = x;
  }
  bool empty() const { return items_.empty(); }
  size_t size() const { return items_.size(); }
  Tick next_time() const { return items_.empty() ? kUnknown : items_.back().when; }
  uint32_t pop() {
    const uint32_t r = items_.back().ray;
    items_.pop_back();
    return r;
  }

 private:
  struct Item {
    Tick when;
    uint32_t ray;
    bool before(const Item& o) const { return when != o.when ? when < o.when : ray < o.ray; }
  };
  std::vector<Item> items_;  // latest first
};

}  // namespace rtsim::model
