// A TLM-2.0 base protocol checker of our own: a pass-through module put between an initiator and
// a target (bind the initiator to `target_socket`, `initiator_socket` to the target) that
// forwards every call unchanged, in both directions, and checks each one (IEEE 1666-2011,
// section 15.2):
//  - phase order per transaction: BEGIN_REQ, END_REQ, BEGIN_RESP, END_RESP, each at a time not
//    before the previous one (the call's time plus its annotated delay), a BEGIN_RESP standing for
//    a missing END_REQ, TLM_COMPLETED ending the transaction at any phase;
//  - the request exclusion rule: no BEGIN_REQ while another request awaits its END_REQ, nor
//    timed inside the previous request's BEGIN_REQ-to-END_REQ window (while the target was
//    taking it; a BEGIN_REQ timed before that window is legal: times need only grow within a
//    transaction, 15.2.7; a response returned from the BEGIN_REQ call, TLM_COMPLETED or
//    BEGIN_RESP, times the response, not the request, whose window is then empty); the response
//    exclusion rule likewise for BEGIN_RESP and END_RESP;
//  - one transaction per payload: a payload is not sent again before its transaction ends;
//  - the fields of a request (a read or a write, a data pointer, a length, a streaming width not
//    below it, the response status TLM_INCOMPLETE_RESPONSE) and of a response (a status set);
//  - the return values: TLM_ACCEPTED leaves the phase, TLM_UPDATED moves it forward.
// b_transport, transport_dbg and DMI pass through (b_transport's fields are checked too). The
// first violation is reported as rtsim/tlm (model/sim/report.h), naming the rule, the payload's
// address and the phases.
#pragma once

#include "model/sim/stats_description.h"
#include "model/sim/stats_registry.h"
#include "model/sim/systemc_time.h"
#include "model/sim/time.h"

#include <tlm_utils/simple_initiator_socket.h>
#include <tlm_utils/simple_target_socket.h>
#include <systemc>
#include <tlm>

#include <cstdint>
#include <string>
#include <unordered_map>

namespace rtsim::model {

struct TlmCheckerStats {
  uint64_t transactions = 0;
  uint64_t phases = 0;
};

// Every TlmCheckerStats field, once (model/sim/stats_description.h).
template <class V>
void describe_stats(V& v, const TlmCheckerStats& s) {
  v.counter("transactions", s.transactions, "count",
            "transactions checked (BEGIN_REQs and b_transport calls)");
  v.counter("phases", s.phases, "count", "phase transitions checked");
}

class TlmChecker : public sc_core::sc_module {
 public:
  tlm_utils::simple_target_socket<TlmChecker> target_socket;        // the initiator binds here
  tlm_utils::simple_initiator_socket<TlmChecker> initiator_socket;  // bound to the target

  explicit TlmChecker(sc_core::sc_module_name name);
  const char* kind() const override { return "rtsim_tlm_checker"; }

  // Transactions not yet ended (0 after a run whose every transaction completed).
  size_t open_transactions() const { return open_.size(); }
  const TlmCheckerStats& stats() const { return stats_; }
  void register_stats(StatsRegistry& r, const std::string& prefix) const;

 private:
  enum class Phase { kBeginReq, kEndReq, kBeginResp };
  struct Open {
    Phase phase;
    Tick at;  // the time of its last phase
  };

  struct Window {
    Tick from = 0, until = 0;
    bool holds(Tick t) const { return t >= from && t < until; }
  };

  tlm::tlm_sync_enum nb_transport_fw(tlm::tlm_generic_payload& p, tlm::tlm_phase& phase,
                                     sc_core::sc_time& delay);
  tlm::tlm_sync_enum nb_transport_bw(tlm::tlm_generic_payload& p, tlm::tlm_phase& phase,
                                     sc_core::sc_time& delay);
  void b_transport(tlm::tlm_generic_payload& p, sc_core::sc_time& delay);
  unsigned transport_dbg(tlm::tlm_generic_payload& p);
  bool get_direct_mem_ptr(tlm::tlm_generic_payload& p, tlm::tlm_dmi& dmi);
  void invalidate_direct_mem_ptr(sc_dt::uint64 start, sc_dt::uint64 end);

  // The checks of one phase transition of `p` at time `at` (BEGIN_REQ is checked by begin()).
  void begin(const tlm::tlm_generic_payload& p, Tick at);
  void transition(const tlm::tlm_generic_payload& p, const tlm::tlm_phase& phase, Tick at,
                  const char* how);
  void complete(const tlm::tlm_generic_payload& p, Tick at, const char* how);
  // If `p` holds the channel (`holder`) it held since `from`: free, busy until `at`.
  static void free_if_held(const tlm::tlm_generic_payload*& holder, Window& busy,
                           const tlm::tlm_generic_payload& p, Tick from, Tick at);
  void check_request_fields(const tlm::tlm_generic_payload& p);
  void check_response_status(const tlm::tlm_generic_payload& p, const char* how);
  // After a call returned: what its return value says.
  void returned(const tlm::tlm_generic_payload& p, tlm::tlm_sync_enum r,
                const tlm::tlm_phase& before, const tlm::tlm_phase& after, Tick at,
                const char* path);
  [[noreturn]] void violation(const tlm::tlm_generic_payload& p, const std::string& rule) const;
  void end_of_elaboration() override { time_ = TimeBase::kernel(); }
  Tick time_of(const sc_core::sc_time& delay) const {
    return time_.to_tick(sc_core::sc_time_stamp() + delay);
  }

  std::unordered_map<const tlm::tlm_generic_payload*, Open> open_;
  const tlm::tlm_generic_payload* request_ = nullptr;   // awaiting its END_REQ
  const tlm::tlm_generic_payload* response_ = nullptr;  // awaiting its END_RESP
  Window request_busy_, response_busy_;                 // the last request's and response's
  TlmCheckerStats stats_;
  TimeBase time_;
};

}  // namespace rtsim::model
