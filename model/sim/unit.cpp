#include "model/sim/unit.h"

#include <algorithm>

namespace rtsim::model {

Unit::Unit(sc_core::sc_module_name name, Calendar& calendar, const Clock& clock)
    : sc_core::sc_module(name), calendar_(calendar), clock_(clock) {
  calendar_.add(this, clock.period());
}

void Unit::activate() {
  const Tick now = now_ps();
  // The gap since the last activation: stalled if the unit held work, idle otherwise.
  if (now > accounted_to_) {
    const uint64_t gap = clock_.to_cycles(now - accounted_to_);
    (held_work_ ? stats_.stalled_cycles : stats_.idle_cycles) += gap;
  }
  const bool issued = cycle(now);
  if (issued) {
    last_issue_ = now;
    ++stats_.busy_cycles;
  } else {
    (holds_work() ? stats_.stalled_cycles : stats_.idle_cycles) += 1;
  }
  accounted_to_ = now + clock_.period();
  held_work_ = holds_work();
  const Tick next = next_ready(now + clock_.period());
  if (next != kUnknown) wake(next);
}

void Unit::finish_accounting(Tick end) {
  if (end > accounted_to_) {
    const uint64_t gap = clock_.to_cycles(end - accounted_to_);
    (held_work_ ? stats_.stalled_cycles : stats_.idle_cycles) += gap;
    accounted_to_ = end;
  }
}

void Unit::register_unit_stats(StatsRegistry& r, const std::string& prefix) const {
  r.counter(prefix + ".busy_cycles", &stats_.busy_cycles, "cycles",
            "cycles in which an operation issued");
  r.counter(prefix + ".stalled_cycles", &stats_.stalled_cycles, "cycles",
            "cycles holding work that could not issue");
  r.counter(prefix + ".idle_cycles", &stats_.idle_cycles, "cycles", "cycles without work");
}

}  // namespace rtsim::model
