// The model's picoseconds (Tick) against SystemC's time, whose resolution is the platform's
// choice (sc_set_time_resolution): every conversion between the two goes through here. A model
// time becomes an sc_time rounded up to the resolution (an event never fires before the time it
// stands for); an sc_time becomes picoseconds exactly when the resolution is a whole number of
// them, rounded up when it is finer. The accelerator's clock edges must be representable: the
// calendar checks its clock against the resolution at the end of elaboration (rtsim/config).
#pragma once

#include "model/sim/time.h"

#include <systemc>

#include <string>

namespace rtsim::model {

class TimeBase {
 public:
  TimeBase() = default;  // 1 ps, without asking the kernel
  // The kernel's resolution. Asking fixes it (SystemC refuses sc_set_time_resolution after any
  // sc_time other than zero was made): blocks ask at the end of elaboration, not when built.
  static TimeBase kernel();

  Tick to_tick(const sc_core::sc_time& t) const {
    const uint64_t v = t.value();
    return units_per_ps_ == 1 ? v * ps_per_unit_ : (v + units_per_ps_ - 1) / units_per_ps_;
  }
  sc_core::sc_time to_sc_time(Tick ps) const {
    return sc_core::sc_time::from_value(units_per_ps_ == 1 ? (ps + ps_per_unit_ - 1) / ps_per_unit_
                                                           : ps * units_per_ps_);
  }
  Tick now() const { return to_tick(sc_core::sc_time_stamp()); }
  // From the kernel's present time to model time `at` (zero if that is past).
  sc_core::sc_time delay_until(Tick at) const {
    const sc_core::sc_time t = to_sc_time(at);
    const sc_core::sc_time& stamp = sc_core::sc_time_stamp();
    return t > stamp ? t - stamp : sc_core::SC_ZERO_TIME;
  }

  // Whether every multiple of `ps` is a whole number of resolution units.
  bool holds(Tick ps) const { return units_per_ps_ > 1 || ps % ps_per_unit_ == 0; }
  // The coarsest resolution (1 fs times a power of ten) that holds `ps`, as text ("1 ns").
  static std::string coarsest_holding(Tick ps);
  std::string resolution() const;  // the kernel's, as text
  Tick resolution_ps() const { return units_per_ps_ > 1 ? 0 : ps_per_unit_; }  // 0: below 1 ps

 private:
  uint64_t ps_per_unit_ = 1;   // a resolution of 1 ps or coarser
  uint64_t units_per_ps_ = 1;  // a finer one (1, 10 or 100 fs)
};

}  // namespace rtsim::model
