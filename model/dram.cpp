#include "model/dram.h"

#include <algorithm>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace rtsim::model {

namespace {

Tick sim_now_ps() { return Scheduler::instance().now(); }  // resolution is 1 ps

}  // namespace

Dram::Dram(sc_core::sc_module_name name, const DramConfig& config, const std::vector<uint8_t>* memory,
           const Clock& accel_clock)
    : sc_core::sc_module(name), engine_(config), memory_(memory), accel_clock_(accel_clock) {
  if (sc_core::sc_get_time_resolution() != sc_core::sc_time(1, sc_core::SC_PS))
    throw std::logic_error("Dram needs sc_set_time_resolution(1, SC_PS)");
  Scheduler::instance().add(this);
}

Tick Dram::fetch_line(uint64_t line_addr, Tick now, FillListener* listener, uint64_t cookie) {
  const Tick sim_now = sim_now_ps();
  if (now < sim_now) now = sim_now;
  if (line_addr % engine_.config().request_bytes != 0)
    throw std::logic_error("DRAM fetch_line: address " + std::to_string(line_addr) + " is not aligned to request_bytes (" +
                           std::to_string(engine_.config().request_bytes) + ")");
  if (memory_) line_data(line_addr);  // a request outside the image is a caller's bug: fail here
  const uint64_t id = next_id_++;
  requesters_.emplace(id, Requester{line_addr, listener, cookie});
  engine_.enqueue(line_addr, now, id);
  wake_for(engine_.next_event_time());
  return kUnknown;
}

const uint8_t* Dram::line_data(uint64_t line_addr) const {
  const uint64_t bytes = engine_.config().request_bytes;
  if (!memory_ || line_addr > memory_->size() || memory_->size() - line_addr < bytes) {
    char addr[24];
    std::snprintf(addr, sizeof addr, "0x%llx", static_cast<unsigned long long>(line_addr));
    throw std::out_of_range(std::string("DRAM line ") + addr + " (" + std::to_string(bytes) +
                            " bytes) is outside the memory image (" + std::to_string(memory_ ? memory_->size() : 0) +
                            " bytes)");
  }
  return memory_->data() + line_addr;
}

void Dram::activate() {
  const Tick now = sim_now_ps();
  done_.clear();
  engine_.advance(now, done_);
  for (const DramController::Completion& c : done_)
    deliveries_.push(Delivery{accel_clock_.edge_at_or_after(c.data_ready), c.id});
  while (!deliveries_.empty() && deliveries_.top().when <= now) {
    const Delivery d = deliveries_.top();
    deliveries_.pop();
    const auto it = requesters_.find(d.id);
    const Requester r = it->second;
    requesters_.erase(it);
    // on_fill may call fetch_line again (it re-arms this module; the earliest time wins).
    if (r.listener) r.listener->on_fill(r.line, r.cookie, d.when);
  }
  Tick next = engine_.next_event_time();
  if (!deliveries_.empty()) next = std::min(next, deliveries_.top().when);
  wake_for(next);
}

void Dram::wake_for(Tick t) {
  if (t != kUnknown) Scheduler::instance().schedule(this, t);  // a pending earlier time stands
}

}  // namespace rtsim::model
