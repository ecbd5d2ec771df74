#include "model/sim/calendar.h"

#include "model/sim/report.h"

#include <algorithm>
#include <climits>
#include <string>

namespace rtsim::model {

Calendar::Calendar(sc_core::sc_module_name name) : sc_core::sc_module(name) {
  SC_METHOD(run);
  sensitive << event_;
  dont_initialize();
  ring_.assign(kSlots * words_, 0);
}

void Calendar::end_of_elaboration() {
  time_ = TimeBase::kernel();  // not in the constructor: the platform may set it after
  if (period_ != 0 && !time_.holds(period_))
    report_error(kReportConfig, std::string(name()) + ": a clock period of " +
                                    std::to_string(period_) + " ps needs a time resolution of " +
                                    TimeBase::coarsest_holding(period_) + " or finer, not " +
                                    time_.resolution() + " (sc_set_time_resolution)");
}

void Calendar::add(Client* c, Tick period) {
  if (fixed_)
    report_error(kReportInternal,
                 std::string(name()) + ": blocks must be added before any is scheduled");
  c->period_ = period;
  clients_.push_back(c);
  if (period_ == 0 && period != 0) {
    period_ = period;
    ring_clock_ = Clock::with_period(period);
  }
}

void Calendar::set_rank(Client& c, uint32_t rank) {
  if (fixed_)
    report_error(kReportInternal,
                 std::string(name()) + ": ranks must be given before any block is scheduled");
  c.rank_ = rank;
}

void Calendar::fix_order() {
  std::stable_sort(clients_.begin(), clients_.end(),
                   [](const Client* a, const Client* b) { return a->rank_ < b->rank_; });
  for (size_t i = 0; i < clients_.size(); ++i) clients_[i]->id_ = uint32_t(i);
  words_ = (clients_.size() + 63) / 64;
  ring_.assign(kSlots * words_, 0);
  fixed_ = true;
}

void Calendar::notify_at(Tick at) {
  event_at_ = at;
  event_.notify(time_.delay_until(at));
}

// Inlined into run(): it runs once per activation.
inline bool Calendar::pop_due(Tick now, const Due& due, uint32_t& id) {
  const bool heap_due = heap_next_ == now;
  if (due.edge) {
    uint64_t* words = &ring_[due.slot * words_];
    for (size_t w = 0; w < words_; ++w) {
      if (!words[w]) continue;
      const uint32_t lowest = uint32_t(w * 64 + __builtin_ctzll(words[w]));
      if (heap_due && heap_.top().id <= lowest) break;
      words[w] &= words[w] - 1;
      --ring_entries_;
      id = lowest;
      return true;
    }
  }
  if (!heap_due) return false;
  id = heap_.top().id;
  heap_.pop();
  heap_next_ = heap_.empty() ? kUnknown : heap_.top().at;
  return true;
}

bool Calendar::slot_empty(uint64_t slot) const {
  for (size_t w = 0; w < words_; ++w)
    if (ring_[slot * words_ + w]) return false;
  return true;
}

Tick Calendar::next_time(Tick now) {
  Tick next = heap_next_;
  if (ring_entries_ > 0) {
    const uint64_t first = (now + period_ - 1) / period_;  // the first edge at or after now
    for (uint64_t c = first; c < first + kSlots; ++c) {
      if (c * period_ >= next) break;
      if (!slot_empty(c % kSlots)) return c * period_;
    }
  }
  return next;
}

void Calendar::run() {
  const Tick stamp = time_.now();
  // The model time the event stood for: the kernel's present time unless the resolution rounded
  // it up.
  Tick now = std::min(event_at_, stamp);
  event_at_ = kUnknown;
  running_ = true;
  for (;;) {
    now_ = now;
    // Blocks woken for `now` while this runs are served in this same loop: the lowest id queued
    // for `now` runs next.
    uint32_t id = 0;
    Due due;
    if (period_) {
      const uint64_t cycle = ring_clock_.to_cycles(now);
      due = {cycle % kSlots, cycle * period_ == now};
    }
    next_edge_ = due.edge ? now + period_ : kUnknown;
    slot_ = due.slot;
    while (pop_due(now, due, id)) {
      Client* c = clients_[id];
      if (c->armed_at_ != now) continue;  // superseded by an earlier arming
      c->armed_at_ = kUnknown;
      c->activate();
    }
    const Tick next = next_time(now);
    if (next > stamp) {          // kUnknown too
      if (settled_) settled_();  // still running, at `now`
      running_ = false;
      next_edge_ = kUnknown;
      if (next != kUnknown) notify_at(next);
      return;
    }
    now = next;  // a time the resolution rounded up to this one
  }
}

}  // namespace rtsim::model
