// Clock arithmetic in picoseconds.
#pragma once

#include "model/memory_interface.h"

#include <cmath>

namespace rtsim::model {

// A clock of `ghz` gigahertz: converts cycles to ticks and rounds times up to its edges.
class Clock {
 public:
  explicit Clock(double ghz = 1.0) : period_(Tick(std::llround(1000.0 / ghz))) {}
  Tick period() const { return period_; }
  Tick cycles(uint64_t n) const { return n * period_; }
  // The first edge at or after t.
  Tick edge_at_or_after(Tick t) const { return (t + period_ - 1) / period_ * period_; }
  uint64_t to_cycles(Tick t) const { return t / period_; }

 private:
  Tick period_;
};

}  // namespace rtsim::model
