#include "model/scheduler.h"

namespace rtsim::model {

namespace {
Tick now_ps() { return Tick(sc_core::sc_time_stamp().value()); }
}  // namespace

Scheduler& Scheduler::instance() {
  static Scheduler* s = new Scheduler("scheduler");  // lives as long as the SystemC kernel
  return *s;
}

Scheduler::Scheduler(sc_core::sc_module_name name) : sc_core::sc_module(name) {
  SC_METHOD(run);
  sensitive << event_;
  dont_initialize();
}

void Scheduler::add(Client* c) {
  c->id_ = uint32_t(clients_.size());
  clients_.push_back(c);
}

void Scheduler::schedule(Client* c, Tick at) {
  const Tick now = now_ps();
  if (at < now) at = now;
  if (c->armed_at_ != kUnknown && c->armed_at_ <= at && c->armed_at_ >= now) return;
  c->armed_at_ = at;
  calendar_.push({at, c->id_});
  // While run() drains this time it re-arms the event itself.
  if (!running_ && at < event_at_) {
    event_at_ = at;
    event_.notify(sc_core::sc_time::from_value(at - now));
  }
}

void Scheduler::run() {
  const Tick now = now_ps();
  event_at_ = kUnknown;
  running_ = true;
  // Clients woken for `now` while this runs are served in this same loop, in id order among the
  // entries still queued.
  while (!calendar_.empty() && calendar_.top().at <= now) {
    const Entry e = calendar_.top();
    calendar_.pop();
    Client* c = clients_[e.id];
    if (c->armed_at_ != e.at) continue;  // superseded by an earlier arming
    c->armed_at_ = kUnknown;
    c->activate();
  }
  running_ = false;
  if (!calendar_.empty()) {
    event_at_ = calendar_.top().at;
    event_.notify(sc_core::sc_time::from_value(event_at_ - now));
  }
}

}  // namespace rtsim::model
