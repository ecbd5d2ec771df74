// The common shape of every pipelined unit: activations on the calendar, only when the
// unit has work. An activation does one cycle's work (`cycle`), then the unit re-arms itself for
// the next cycle if more work is ready by then, for the earliest future ready time, or not at all
// (idle until something calls wake()). Busy, stalled and idle cycles are accounted from these
// transitions: a cycle is busy when an operation issued, stalled when the unit held work it could
// not issue (waiting on memory or on a full output), idle otherwise.
#pragma once

#include "model/sim/calendar.h"
#include "model/sim/stats_description.h"
#include "model/sim/stats_registry.h"
#include "model/sim/time.h"

#include <systemc>

#include <algorithm>
#include <string>

namespace rtsim::model {

struct UnitStats {
  uint64_t busy_cycles = 0;
  uint64_t stalled_cycles = 0;
  uint64_t idle_cycles = 0;
};

// Every UnitStats field, once (model/sim/stats_description.h).
template <class V>
void describe_stats(V& v, const UnitStats& s) {
  v.counter("busy_cycles", s.busy_cycles, "cycles", "cycles in which an operation issued");
  v.counter("stalled_cycles", s.stalled_cycles, "cycles",
            "cycles holding work that could not issue");
  v.counter("idle_cycles", s.idle_cycles, "cycles", "cycles without work");
}

// The calendar's side first: it calls activate() without adjusting `this` (no thunk, and profiles
// see the activation's lines).
class Unit : public Calendar::Client, public sc_core::sc_module {
 public:
  // Schedules an activation at time `at` (or at once if `at` has passed); the earliest wins.
  // Never twice in one cycle: the earliest next activation is the cycle after the last one.
  void wake(Tick at) {
    calendar_.schedule(this,
                       clock_.edge_at_or_after(std::max({at, calendar_.now(), accounted_to_})));
  }
  // Closes the accounting at `end` (the end of the run).
  void finish_accounting(Tick end);
  const UnitStats& unit_stats() const { return stats_; }
  void register_unit_stats(StatsRegistry& r, const std::string& prefix) const;
  const Clock& clock() const { return clock_; }
  // Whether an operation issued at clock edge `edge` (the latest edge only).
  bool issued_at(Tick edge) const { return last_issue_ == edge; }

 protected:
  Unit(sc_core::sc_module_name name, Calendar& calendar, const Clock& clock);

  // One cycle at `now` (a clock edge). Returns true if an operation issued.
  virtual bool cycle(Tick now) = 0;
  // The earliest time at or after `from` at which cycle() could issue; kUnknown if it cannot
  // until woken from outside.
  virtual Tick next_ready(Tick from) const = 0;
  // True while the unit holds work (for stalled versus idle).
  virtual bool holds_work() const = 0;

  Tick now_ps() const { return calendar_.now(); }
  Calendar& calendar() const { return calendar_; }

  // One activation as activate() does it, with the steps seen as `U`'s: a unit whose steps are
  // final overrides activate() with activate_as<Self>() and the compiler calls them directly (the
  // ray units: one activation per operation, millions per frame). `U` befriends Unit.
  template <class U>
  void activate_as() {
    U& u = static_cast<U&>(*this);
    const Tick now = now_ps();
    // The gap since the last activation: stalled if the unit held work, idle otherwise.
    if (now > accounted_to_) {
      const uint64_t gap = clock_.to_cycles(now - accounted_to_);
      (held_work_ ? stats_.stalled_cycles : stats_.idle_cycles) += gap;
    }
    const bool issued = u.cycle(now);
    held_work_ = u.holds_work();
    if (issued) {
      last_issue_ = now;
      ++stats_.busy_cycles;
    } else {
      ++(held_work_ ? stats_.stalled_cycles : stats_.idle_cycles);
    }
    accounted_to_ = now + clock_.period();
    const Tick next = u.next_ready(accounted_to_);
    if (next == accounted_to_)
      calendar_.schedule_next(this, next);  // busy: the next cycle
    else if (next != kUnknown)
      wake(next);
  }

 private:
  void activate() override { activate_as<Unit>(); }

  Calendar& calendar_;
  const Clock clock_;       // a copy: a temporary clock cannot outlive the unit
  Tick accounted_to_ = 0;   // cycles before this are classified
  bool held_work_ = false;  // state of the gap since the last activation
  Tick last_issue_ = kUnknown;
  UnitStats stats_;
};

}  // namespace rtsim::model
