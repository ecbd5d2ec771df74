// The cycles a port (a cache bank, a link's end) is taken. A port serves `ports` accesses per cycle
// of its clock; a request for time t gets the first cycle at or after t with a slot left, and keeps
// it: requests are served first come, first served in the order they are made (the calendar's
// fixed order), and one made later never takes a slot already given. Requests may ask for future
// times (a miss reaches the next level a hit latency later), so the schedule is a calendar of
// slots, not a single busy-until stamp: an earlier time asked later still finds the idle cycles
// before a later reservation.
//
// A full cycle points at a later cycle that may have room (union-find with path compression), so
// k requests piling up on one cycle cost O(k α(k)) in all, not O(k^2). Cycles live in a ring that
// recycles the ones before the simulated time and doubles when reservations reach further ahead.
//
// `ports == 0` is the ideal port: every request is served at once and nothing is recorded but the
// count.
#pragma once

#include "model/memory_interface.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace rtsim::model {

struct PortStats {
  uint64_t requests = 0;      // slots asked for
  uint64_t delayed = 0;       // requests served later than asked
  uint64_t wait_cycles = 0;   // sum over requests of (cycle served - cycle asked)
  uint64_t max_wait_cycles = 0;
};

class PortSchedule {
 public:
  // `period`: the port's clock period (ps); `ports`: slots per cycle (0: unlimited).
  PortSchedule(Tick period, uint32_t ports);

  // The edge of the first cycle at or after `t` with a free slot, which is taken.
  Tick reserve(Tick t);
  // `n` slots, one per cycle, the first at or after `t`, each after the previous: the cycle of
  // the last (a transfer of n flits over the port). n >= 1.
  Tick reserve_run(Tick t, uint32_t n);

  bool ideal() const { return ports_ == 0; }
  uint32_t ports() const { return ports_; }
  Tick period() const { return period_; }
  const PortStats& stats() const { return stats_; }

 private:
  static constexpr uint64_t kEmpty = ~uint64_t(0);
  uint64_t find(uint64_t cycle);  // the first cycle >= `cycle` with room
  size_t slot(uint64_t cycle);    // the ring index holding `cycle`, made fresh if it held a dead one
  void grow();

  Tick period_;
  uint32_t ports_;
  uint64_t mask_ = 0;
  std::vector<uint64_t> cycle_;  // the cycle a ring entry holds (kEmpty: none)
  std::vector<uint32_t> used_;   // slots taken in that cycle
  std::vector<uint64_t> next_;   // full cycles: a later cycle that may have room
  std::vector<uint64_t> path_;   // scratch for path compression
  PortStats stats_;
};

}  // namespace rtsim::model
