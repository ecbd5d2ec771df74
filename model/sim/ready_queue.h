// Rays waiting inside a unit, ordered by the time they can issue (then by id: deterministic).
#pragma once

#include "model/sim/time.h"

#include <cstdint>
#include <queue>
#include <vector>

namespace rtsim::model {

class ReadyQueue {
 public:
  void push(Tick when, uint32_t ray) { heap_.push({when, ray}); }
  bool empty() const { return heap_.empty(); }
  size_t size() const { return heap_.size(); }
  Tick next_time() const { return heap_.empty() ? kUnknown : heap_.top().when; }
  uint32_t pop() {
    const uint32_t r = heap_.top().ray;
    heap_.pop();
    return r;
  }

 private:
  struct Item {
    Tick when;
    uint32_t ray;
    bool operator>(const Item& o) const { return when != o.when ? when > o.when : ray > o.ray; }
  };
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> heap_;
};

}  // namespace rtsim::model
