// Not a hardware block: an observer that runs a function every `period` from a start time until
// the function returns false (progress reports, trace sampling). Its own event, off the clock
// edges if asked, so it sees the state after every unit has acted at an edge.
#pragma once

#include "model/sim/time.h"

#include <systemc>

#include <functional>

namespace rtsim::model {

class PeriodicProbe : public sc_core::sc_module {
 public:
  SC_HAS_PROCESS(PeriodicProbe);
  PeriodicProbe(sc_core::sc_module_name name, Tick period_ps, std::function<bool(Tick)> sample)
      : sc_core::sc_module(name), period_(period_ps), sample_(std::move(sample)) {
    SC_METHOD(run);
    sensitive << event_;
    dont_initialize();
  }
  void start_at(Tick at) {
    const Tick now = Tick(sc_core::sc_time_stamp().value());
    event_.notify(sc_core::sc_time::from_value(at > now ? at - now : 0));
  }

 private:
  void run() {
    if (sample_(Tick(sc_core::sc_time_stamp().value())))
      event_.notify(sc_core::sc_time::from_value(period_));
  }

  Tick period_;
  std::function<bool(Tick)> sample_;
  sc_core::sc_event event_;
};

}  // namespace rtsim::model
