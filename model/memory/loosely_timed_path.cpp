// sc_spawn: the pool threads are made while the simulation runs.
#define SC_INCLUDE_DYNAMIC_PROCESSES
#include "model/memory/loosely_timed_path.h"

#include <algorithm>
#include <cstring>

namespace rtsim::model {

struct LooselyTimedPath::Worker {
  sc_core::sc_event go;
  tlm::tlm_generic_payload* payload = nullptr;
  sc_core::sc_time delay;
};

LooselyTimedPath::LooselyTimedPath(std::string name,
                                   std::function<tlm::tlm_fw_transport_if<>*()> target,
                                   Answered answered)
    : name_(std::move(name)), target_(std::move(target)), answered_(std::move(answered)) {}

LooselyTimedPath::~LooselyTimedPath() = default;

void LooselyTimedPath::send(tlm::tlm_generic_payload& p, Tick now, Tick at, const TimeBase& time) {
  time_ = time;
  if (through_dmi(p, at)) return;
  if (idle_.empty()) {
    workers_.push_back(std::make_unique<Worker>());
    Worker* w = workers_.back().get();
    sc_core::sc_spawn_options opts;
    opts.set_sensitivity(&w->go);
    opts.dont_initialize();
    // Named under the process that spawns it (the calendar's)
    sc_core::sc_spawn([this, w] { run(w); },
                      (name_ + "_lt_call" + std::to_string(workers_.size() - 1)).c_str(), &opts);
    idle_.push_back(w);
  }
  Worker* w = idle_.back();
  idle_.pop_back();
  // The threads are kept for later frames; the statistic is the most calls in flight at once.
  stats_.lt_threads = std::max<uint64_t>(stats_.lt_threads, workers_.size() - idle_.size());
  w->payload = &p;
  w->delay = time.to_sc_time(at - now);
  w->go.notify(sc_core::SC_ZERO_TIME);  // the call is made in the next delta, at this time
}

void LooselyTimedPath::run(Worker* w) {
  for (;;) {
    tlm::tlm_generic_payload& p = *w->payload;
    sc_core::sc_time delay = w->delay;
    ++stats_.lt_calls;
    target_()->b_transport(p, delay);
    if (p.is_response_ok() && p.is_dmi_allowed() && !region_for(p)) ask_dmi(p);
    const Tick done = time_.to_tick(sc_core::sc_time_stamp() + delay);
    idle_.push_back(w);
    answered_(p, done);
    sc_core::wait(w->go);
  }
}

const tlm::tlm_dmi* LooselyTimedPath::region_for(const tlm::tlm_generic_payload& p) const {
  const uint64_t a = p.get_address(), n = p.get_data_length();
  for (const tlm::tlm_dmi& d : regions_)
    if (a >= d.get_start_address() && a + n - 1 <= d.get_end_address() &&
        (p.is_write() ? d.is_write_allowed() : d.is_read_allowed()))
      return &d;
  return nullptr;
}

bool LooselyTimedPath::through_dmi(tlm::tlm_generic_payload& p, Tick at) {
  const tlm::tlm_dmi* d = region_for(p);
  if (!d) return false;
  const uint64_t n = p.get_data_length();
  unsigned char* mem = d->get_dmi_ptr() + (p.get_address() - d->get_start_address());
  if (p.is_write())
    std::memcpy(mem, p.get_data_ptr(), n);
  else
    std::memcpy(p.get_data_ptr(), mem, n);
  p.set_response_status(tlm::TLM_OK_RESPONSE);
  ++stats_.dmi_accesses;
  const sc_core::sc_time latency = p.is_write() ? d->get_write_latency() : d->get_read_latency();
  answered_(p, at + time_.to_tick(latency));
  return true;
}

void LooselyTimedPath::ask_dmi(tlm::tlm_generic_payload& p) {
  tlm::tlm_generic_payload q;
  q.set_command(p.get_command());
  q.set_address(p.get_address());
  tlm::tlm_dmi d;
  if (target_()->get_direct_mem_ptr(q, d) && d.get_dmi_ptr()) regions_.push_back(d);
}

void LooselyTimedPath::invalidate(uint64_t start, uint64_t end) {
  regions_.erase(std::remove_if(regions_.begin(), regions_.end(),
                                [&](const tlm::tlm_dmi& d) {
                                  return d.get_start_address() <= end &&
                                         d.get_end_address() >= start;
                                }),
                 regions_.end());
}

void LooselyTimedPath::register_stats(StatsRegistry& r, const std::string& prefix) const {
  StatsRegistrar v(r, prefix);
  describe_stats(v, stats_);
}

}  // namespace rtsim::model
