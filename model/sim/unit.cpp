#include "model/sim/unit.h"

#include <algorithm>

namespace rtsim::model {

Unit::Unit(sc_core::sc_module_name name, Calendar& calendar, const Clock& clock)
    : sc_core::sc_module(name), calendar_(calendar), clock_(clock) {
  calendar_.add(this, clock.period());
}

void Unit::finish_accounting(Tick end) {
  if (end > accounted_to_) {
    const uint64_t gap = clock_.to_cycles(end - accounted_to_);
    (held_work_ ? stats_.stalled_cycles : stats_.idle_cycles) += gap;
    accounted_to_ = end;
  }
}

void Unit::register_unit_stats(StatsRegistry& r, const std::string& prefix) const {
  StatsRegistrar v(r, prefix);
  describe_stats(v, stats_);
}

}  // namespace rtsim::model
