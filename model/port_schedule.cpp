#include "model/port_schedule.h"

#include <systemc>

#include <algorithm>
#include <stdexcept>

namespace rtsim::model {

namespace {

constexpr size_t kInitialCycles = 256;

uint64_t sim_cycle(Tick period) { return uint64_t(sc_core::sc_time_stamp().value()) / period; }

}  // namespace

PortSchedule::PortSchedule(Tick period, uint32_t ports) : period_(period), ports_(ports) {
  if (period_ == 0) throw std::invalid_argument("PortSchedule: zero clock period");
  if (ports_ == 0) return;
  mask_ = kInitialCycles - 1;
  cycle_.assign(kInitialCycles, kEmpty);
  used_.assign(kInitialCycles, 0);
  next_.assign(kInitialCycles, 0);
}

size_t PortSchedule::slot(uint64_t cycle) {
  for (;;) {
    const size_t i = size_t(cycle & mask_);
    if (cycle_[i] == cycle) return i;
    // The entry holds another cycle: reuse it if that one is over, else make room.
    if (cycle_[i] == kEmpty || cycle_[i] < sim_cycle(period_)) {
      cycle_[i] = cycle;
      used_[i] = 0;
      next_[i] = cycle + 1;
      return i;
    }
    grow();
  }
}

void PortSchedule::grow() {
  const uint64_t now = sim_cycle(period_);
  size_t size = cycle_.size();
  for (;;) {
    size *= 2;
    const uint64_t mask = size - 1;
    std::vector<uint64_t> cycle(size, kEmpty), next(size, 0);
    std::vector<uint32_t> used(size, 0);
    bool clash = false;
    for (size_t i = 0; i < cycle_.size() && !clash; ++i) {
      if (cycle_[i] == kEmpty || cycle_[i] < now) continue;
      const size_t j = size_t(cycle_[i] & mask);
      clash = cycle[j] != kEmpty;
      cycle[j] = cycle_[i];
      used[j] = used_[i];
      next[j] = next_[i];
    }
    if (clash) continue;
    cycle_.swap(cycle);
    used_.swap(used);
    next_.swap(next);
    mask_ = mask;
    return;
  }
}

uint64_t PortSchedule::find(uint64_t cycle) {
  path_.clear();
  for (;;) {
    const size_t i = slot(cycle);
    if (used_[i] < ports_) break;
    path_.push_back(cycle);
    cycle = next_[i];
  }
  // Every full cycle passed on the way now points straight at the one with room.
  for (const uint64_t c : path_) next_[slot(c)] = cycle;
  return cycle;
}

Tick PortSchedule::reserve(Tick t) {
  ++stats_.requests;
  if (ports_ == 0) return t;
  const uint64_t asked = (t + period_ - 1) / period_;
  const uint64_t got = find(asked);
  const size_t i = slot(got);
  if (++used_[i] == ports_) next_[i] = got + 1;
  if (got > asked) {
    ++stats_.delayed;
    stats_.wait_cycles += got - asked;
    stats_.max_wait_cycles = std::max(stats_.max_wait_cycles, got - asked);
  }
  return got * period_;
}

Tick PortSchedule::reserve_run(Tick t, uint32_t n) {
  Tick last = reserve(t);
  for (uint32_t k = 1; k < n; ++k) last = reserve(last + period_);
  return last;
}

}  // namespace rtsim::model
