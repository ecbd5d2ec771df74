// Not a hardware block: an observer that runs a function every `period` from a start time until
// the function returns false (progress reports, trace sampling). Its own event, off the clock
// edges if asked, so it sees the state after every unit has acted at an edge.
#pragma once

#include "model/sim/systemc_time.h"
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
  // `at` and every period after it, each rounded up to the resolution.
  void start_at(Tick at) {
    next_ = at;
    event_.notify(time_.delay_until(at));
  }

 private:
  void end_of_elaboration() override { time_ = TimeBase::kernel(); }
  void run() {
    if (!sample_(next_)) return;
    next_ += period_;
    event_.notify(time_.delay_until(next_));
  }

  Tick period_;
  Tick next_ = 0;  // the model time of the next sample
  TimeBase time_;
  std::function<bool(Tick)> sample_;
  sc_core::sc_event event_;
};

}  // namespace rtsim::model
