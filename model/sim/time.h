// The model's time: one base in picoseconds (Tick), so the accelerator clock (1 GHz by default)
// and the DRAM's own command clock share it (SystemC's resolution is 1 ps), and clock arithmetic.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>

namespace rtsim::model {

using Tick = uint64_t;                                              // picoseconds
inline constexpr Tick kUnknown = std::numeric_limits<Tick>::max();  // a time not known yet

// A clock of `ghz` gigahertz: converts cycles to ticks and rounds times up to its edges.
// Divisions by the period are multiplications by its reciprocal (exact below kExact: Granlund and
// Montgomery's method; a 64-bit division costs tens of cycles and these run on every access).
class Clock {
 public:
  explicit Clock(double ghz = 1.0) : Clock(Period{Tick(std::llround(1000.0 / ghz))}) {}
  static Clock with_period(Tick period) { return Clock(Period{period}); }

  Tick period() const { return period_; }
  Tick cycles(uint64_t n) const { return n * period_; }
  // The first edge at or after t.
  Tick edge_at_or_after(Tick t) const { return to_cycles(t + period_ - 1) * period_; }
  uint64_t to_cycles(Tick t) const {
    if (t >= exact_below_) return t / period_;
    return uint64_t((unsigned __int128)t * inverse_ >> 64);
  }
  // Cycles from 0 to the first edge at or after t.
  uint64_t ceil_cycles(Tick t) const { return to_cycles(t + period_ - 1); }

 private:
  struct Period {
    Tick ps;
  };
  explicit Clock(Period p)
      : period_(p.ps < 1 ? 1 : p.ps),
        inverse_(period_ == 1 ? 0 : ~uint64_t(0) / period_ + 1),
        exact_below_(period_ == 1 ? 0 : ~uint64_t(0) / period_ - period_) {}

  Tick period_;
  uint64_t inverse_;  // floor(2^64 / period) + 1
  Tick exact_below_;  // t + period - 1 below 2^64 / period keeps the product exact
};

}  // namespace rtsim::model
