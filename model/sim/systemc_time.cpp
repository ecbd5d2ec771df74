#include "model/sim/systemc_time.h"

#include <cmath>

namespace rtsim::model {

namespace {

// "1 ps", "10 ns": a power of ten of femtoseconds in the largest unit that keeps it whole.
std::string femtoseconds_text(uint64_t fs) {
  static const char* const units[] = {"fs", "ps", "ns", "us", "ms", "s"};
  int unit = 0;
  while (unit < 5 && fs % 1000 == 0) {
    fs /= 1000;
    ++unit;
  }
  return std::to_string(fs) + " " + units[unit];
}

}  // namespace

TimeBase TimeBase::kernel() {
  TimeBase t;
  const double fs = std::round(sc_core::sc_get_time_resolution().to_seconds() * 1e15);
  if (fs >= 1000)
    t.ps_per_unit_ = uint64_t(std::llround(fs / 1000));
  else
    t.units_per_ps_ = uint64_t(std::llround(1000 / fs));
  return t;
}

std::string TimeBase::coarsest_holding(Tick ps) {
  uint64_t fs = 1000;
  while (ps % 10 == 0 && ps > 0 && fs < 1'000'000'000'000'000ull) {
    ps /= 10;
    fs *= 10;
  }
  return femtoseconds_text(fs);
}

std::string TimeBase::resolution() const {
  return femtoseconds_text(units_per_ps_ > 1 ? 1000 / units_per_ps_ : ps_per_unit_ * 1000);
}

}  // namespace rtsim::model
