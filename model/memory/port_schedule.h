// The cycles a port (a cache bank, a link's end) is taken. A port serves `ports` accesses per cycle
// of its clock; a request for time t gets the first cycle at or after t with a slot left, and keeps
// it: requests are served first come, first served in the order they are made (the calendar's
// fixed order), and one made later never takes a slot already given. Requests may ask for future
// times (a miss reaches the next level a hit latency later), so the schedule is a calendar of
// slots, not a single busy-until stamp: an earlier time asked later still finds the idle cycles
// before a later reservation.
//
// The calendar is a ring of bits, one per cycle, set when the cycle's slots are all taken (with a
// count per cycle when a port has several slots): the first free cycle is found 64 cycles at a
// time, and requests piling up on one cycle resume where the previous one found room. The ring
// holds the cycles from the simulated time (read lazily: it only moves on) onwards, and doubles
// when reservations reach further ahead.
//
// `ports == 0` is the ideal port: every request is served at once and nothing is recorded but the
// count.
#pragma once

#include "model/memory/line_source.h"
#include "model/sim/time.h"

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace rtsim::model {

struct PortStats {
  uint64_t requests = 0;     // slots asked for
  uint64_t delayed = 0;      // requests served later than asked
  uint64_t wait_cycles = 0;  // sum over requests of (cycle served - cycle asked)
  uint64_t max_wait_cycles = 0;
};

class alignas(64) PortSchedule {
 public:
  // `period`: the port's clock period (ps); `ports`: slots per cycle (0: unlimited).
  PortSchedule(Tick period, uint32_t ports);

  // The edge of the first cycle at or after `t` with a free slot, which is taken.
  Tick reserve(Tick t) {
    ++stats_.requests;
    return ports_ == 0 ? t : clock_.cycles(reserve_slot(clock_.ceil_cycles(t)));
  }
  // reserve() and peek() in cycles of the port's clock (a crossbar works on its edges).
  uint64_t reserve_cycle(uint64_t c) {
    ++stats_.requests;
    return ports_ == 0 ? c : reserve_slot(c);
  }
  uint64_t peek_cycle(uint64_t c) {
    return ports_ == 0 ? c : first_free_for(std::max(c, base_)).cycle;
  }
  // The edge of the first cycle at or after `t` with a free slot, left free.
  Tick peek(Tick t) { return clock_.cycles(peek_cycle(clock_.ceil_cycles(t))); }
  // Takes every slot of the cycles in [from, until) that is still free (a port held by a stalled
  // sender), without counting them as requests.
  void block(Tick from, Tick until);
  // `n` slots, one per cycle, the first at or after `t`, each after the previous: the cycle of
  // the last (a transfer of n flits over the port). n >= 1.
  Tick reserve_run(Tick t, uint32_t n);
  // Whether a one-slot port has cycles [first, first + n) all free: then n reserve()s asking for
  // them one after the other would get exactly them, and take_run() takes them so.
  bool run_free(uint64_t first, uint32_t n) const {
    if (ports_ != 1 || first < base_ || first + n > held_until_) return false;
    for (uint64_t c = first; c < first + n; ++c)
      if ((full()[word_of(c)] >> (c & 63)) & 1) return false;
    return true;
  }
  void take_run(uint64_t first, uint32_t n) {
    for (uint64_t c = first; c < first + n; ++c) full()[word_of(c)] |= uint64_t(1) << (c & 63);
    stats_.requests += n;
    last_asked_ = last_granted_ = first + n - 1;
  }

  bool ideal() const { return ports_ == 0; }
  uint32_t ports() const { return ports_; }
  Tick period() const { return clock_.period(); }
  const PortStats& stats() const { return stats_; }
  void reset_stats() { stats_ = {}; }

 private:
  static constexpr size_t kFirstWords = 4;
  // The ring: bit c % 64 of word c / 64 set when cycle c has no slot left. Its first 256 cycles
  // are in the object (most ports never need more: no pointer to follow); it moves to the heap
  // and doubles when reservations reach further ahead. `words` points at the ring either way.
  struct Bits {
    uint64_t* words = first.data();
    std::array<uint64_t, kFirstWords> first{};
    std::vector<uint64_t> grown;
    Bits() = default;
    Bits(const Bits& o) : first(o.first), grown(o.grown) { repoint(); }
    Bits& operator=(const Bits& o) {
      first = o.first;
      grown = o.grown;
      repoint();
      return *this;
    }
    void repoint() { words = grown.empty() ? first.data() : grown.data(); }
  };
  uint64_t* full() { return bits_.words; }
  const uint64_t* full() const { return bits_.words; }
  size_t words() const { return mask_ + 1; }
  size_t word_of(uint64_t cycle) const { return size_t(cycle >> 6) & mask_; }
  // Makes the ring hold every cycle up to `cycle` (sliding past the cycles that are over, or
  // growing).
  void hold(uint64_t cycle) {
    if (cycle >= held_until_) slide_or_grow(cycle);
  }
  void slide_or_grow(uint64_t cycle);
  // The first cycle with a free slot for a request asking for `asked`, and its word: the word of
  // the cycle asked for first (inline: most requests find their slot there), then the rest. A
  // pile-up on the last request's cycle resumes where that one found room (see last_asked_).
  struct Free {
    uint64_t cycle;
    uint64_t* word;  // the ring's word holding `cycle`
  };
  Free first_free_for(uint64_t asked) {
    uint64_t c = asked == last_asked_ ? std::max(asked, last_granted_) : asked;
    if (c < held_until_) {
      uint64_t* w = full() + word_of(c);
      const uint64_t free = ~*w & (~uint64_t(0) << (c & 63));
      if (free) return {(c & ~uint64_t(63)) + uint64_t(__builtin_ctzll(free)), w};
    }
    c = first_free_beyond(c);
    return {c, full() + word_of(c)};
  }
  uint64_t first_free_beyond(uint64_t cycle);
  void grow();
  // reserve() of a real port, asked for `cycle`: the cycle granted.
  uint64_t reserve_slot(uint64_t cycle) {
    const uint64_t asked = std::max(cycle, base_);
    // The slot is taken in the word that was found (no second look-up of the ring).
    const auto [c, word] = first_free_for(asked);
    const uint64_t bit = uint64_t(1) << (c & 63);
    if (ports_ == 1 || ++used_[word_of(c) * 64 + (c & 63)] == ports_) *word |= bit;
    last_asked_ = asked;
    last_granted_ = c;
    if (c > asked) {
      ++stats_.delayed;
      stats_.wait_cycles += c - asked;
      stats_.max_wait_cycles = std::max(stats_.max_wait_cycles, c - asked);
    }
    return c;
  }

  // What a request reads and writes, first (a cache's banks are an array of these).
  uint32_t ports_;
  size_t mask_ = kFirstWords - 1;  // words - 1
  Clock clock_;
  uint64_t base_ = 0;  // first cycle held, a multiple of 64; the ring holds 64 * words
  uint64_t held_until_ = kFirstWords * 64;  // base_ + 64 * words
  // The last request's asked and granted cycles: cycles in between were full and stay full, so a
  // pile-up on one cycle resumes the search where the previous request found room.
  uint64_t last_asked_ = ~uint64_t(0), last_granted_ = 0;
  PortStats stats_;
  Bits bits_;
  std::vector<uint8_t> used_;  // ports > 1: slots taken per cycle (index c % cycles held)
};

}  // namespace rtsim::model
