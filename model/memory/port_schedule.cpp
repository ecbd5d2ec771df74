#include "model/memory/port_schedule.h"

#include "model/sim/systemc_time.h"

#include <algorithm>
#include <stdexcept>

namespace rtsim::model {

namespace {

// Asked only while the simulation runs, when the resolution is fixed.
Tick sim_time() {
  static const TimeBase time = TimeBase::kernel();
  return time.now();
}

}  // namespace

PortSchedule::PortSchedule(Tick period, uint32_t ports)
    : ports_(ports), clock_(Clock::with_period(period)) {
  if (period == 0) throw std::invalid_argument("PortSchedule: zero clock period");
  if (ports_ == 0) return;
  if (ports_ > 255) throw std::invalid_argument("PortSchedule: at most 255 slots per cycle");
  if (ports_ > 1) used_.assign(kFirstWords * 64, 0);
}

void PortSchedule::slide_or_grow(uint64_t cycle) {
  const uint64_t held = uint64_t(words()) * 64;
  // Slide past the cycles that are over (nobody asks for a time before the simulated one, less
  // a cycle: a block on another clock may act just before the kernel's time, rounded up to the
  // resolution).
  const uint64_t cycle_now = clock_.to_cycles(sim_time());
  const uint64_t now = (cycle_now > 0 ? cycle_now - 1 : 0) & ~uint64_t(63);
  if (now > base_) {
    const uint64_t stop = std::min(now, base_ + held);
    for (uint64_t c = base_; c < stop; c += 64) {
      full()[word_of(c)] = 0;
      if (!used_.empty()) std::fill_n(&used_[word_of(c) * 64], 64, uint8_t(0));
    }
    base_ = now;
  }
  while (cycle >= base_ + uint64_t(words()) * 64) grow();
  held_until_ = base_ + uint64_t(words()) * 64;
}

void PortSchedule::grow() {
  const size_t n = words();
  std::vector<uint64_t> ring(n * 2, 0);
  std::vector<uint8_t> used(used_.empty() ? 0 : n * 2 * 64, 0);
  for (uint64_t c = base_; c < base_ + n * 64; c += 64) {
    const size_t from = word_of(c), to = size_t(c >> 6) & (n * 2 - 1);
    ring[to] = full()[from];
    if (!used.empty()) std::copy_n(&used_[from * 64], 64, &used[to * 64]);
  }
  bits_.grown.swap(ring);
  bits_.repoint();
  mask_ = bits_.grown.size() - 1;
  used_.swap(used);
}

uint64_t PortSchedule::first_free_beyond(uint64_t c) {
  for (;;) {
    hold(c | 63);
    const uint64_t free = ~full()[word_of(c)] & (~uint64_t(0) << (c & 63));
    if (free) return (c & ~uint64_t(63)) + uint64_t(__builtin_ctzll(free));
    c = (c | 63) + 1;
  }
}

void PortSchedule::block(Tick from, Tick until) {
  if (ports_ == 0) return;
  const uint64_t end = clock_.ceil_cycles(until);
  for (uint64_t c = std::max(clock_.ceil_cycles(from), base_); c < end; ++c) {
    hold(c | 63);
    full()[word_of(c)] |= uint64_t(1) << (c & 63);
    if (ports_ > 1) used_[word_of(c) * 64 + (c & 63)] = uint8_t(ports_);
  }
}

Tick PortSchedule::reserve_run(Tick t, uint32_t n) {
  Tick last = reserve(t);
  for (uint32_t k = 1; k < n; ++k) last = reserve(last + clock_.period());
  return last;
}

}  // namespace rtsim::model
