// The memory port's way to a loosely-timed memory: a target that implements b_transport (and
// maybe DMI) and nothing of nb_transport. Accellera's adapter would turn each BEGIN_REQ into a
// b_transport call and end the request only with its response, so one transaction would be in
// flight; here every request is a b_transport call of its own, from a thread of a pool (a target
// may call wait() inside b_transport), so as many are in flight as the model issues. The port
// sends requests in time order, each when it reaches memory (model/memory/memory_port.h), so the
// calls' annotated times (the kernel's time plus the delay, `at` - `now`) never go back. A call's
// response time is the kernel's time when it returns plus the delay it returns.
//
// DMI: a target that sets the payload's DMI hint after a b_transport is asked for a DMI region;
// later reads (writes) inside a region with read (write) access copy the bytes through its
// pointer, timed by the region's read (write) latency after the request's time, with no call.
// invalidate_direct_mem_ptr drops the regions it names.
//
// Statistics (under the port's prefix): lt_calls (b_transport calls), dmi_accesses, threads (the
// pool's size: the most calls ever in flight at once).
#pragma once

#include "model/sim/stats_description.h"
#include "model/sim/systemc_time.h"
#include "model/sim/time.h"

#include <systemc>
#include <tlm>

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace rtsim::model {

struct LooselyTimedStats {
  uint64_t lt_calls = 0, dmi_accesses = 0, lt_threads = 0;
};

// Every LooselyTimedStats field, once (model/sim/stats_description.h).
template <class V>
void describe_stats(V& v, const LooselyTimedStats& s) {
  v.counter("lt_calls", s.lt_calls, "count", "b_transport calls (a loosely-timed memory)");
  v.counter("dmi_accesses", s.dmi_accesses, "count",
            "reads and writes through a DMI pointer, timed by the region's latency");
  v.counter("lt_threads", s.lt_threads, "count",
            "threads calling b_transport: the most calls in flight at once");
}

class LooselyTimedPath {
 public:
  // A transaction answered: its payload and the model time of its response.
  using Answered = std::function<void(tlm::tlm_generic_payload&, Tick)>;

  // `name`: a prefix for its threads' names; `target`: the socket's forward interface, asked
  // when a call is made (after binding).
  LooselyTimedPath(std::string name, std::function<tlm::tlm_fw_transport_if<>*()> target,
                   Answered answered);
  ~LooselyTimedPath();

  // Sends `p` at model time `now`, to reach memory at `at` (>= now).
  void send(tlm::tlm_generic_payload& p, Tick now, Tick at, const TimeBase& time);
  void invalidate(uint64_t start, uint64_t end);

  void register_stats(StatsRegistry& r, const std::string& prefix) const;

 private:
  struct Worker;
  void run(Worker* w);  // a pool thread
  // The DMI region that covers `p` with its access, if any
  const tlm::tlm_dmi* region_for(const tlm::tlm_generic_payload& p) const;
  bool through_dmi(tlm::tlm_generic_payload& p, Tick at);
  void ask_dmi(tlm::tlm_generic_payload& p);  // unless a region already covers it

  std::string name_;
  std::function<tlm::tlm_fw_transport_if<>*()> target_;
  Answered answered_;
  std::vector<std::unique_ptr<Worker>> workers_;
  std::vector<Worker*> idle_;
  std::vector<tlm::tlm_dmi> regions_;
  TimeBase time_;  // the kernel's resolution (the port's, given with every request)
  LooselyTimedStats stats_;
};

}  // namespace rtsim::model
