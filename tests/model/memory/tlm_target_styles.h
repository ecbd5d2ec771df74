// Memory targets for the tests of the accelerator's TLM-2.0 boundary: one fixed-latency memory
// per legal way a target may answer under the base protocol (IEEE 1666-2011, 15.2), each holding
// its bytes (a write lands when it is taken, a read copies when it is answered) and each keeping
// the request and response exclusion rules itself.
//
//   kAcceptLater     BEGIN_REQ answered TLM_ACCEPTED; END_REQ `accept` later on the backward path;
//                    BEGIN_RESP `latency` after the request's time on the backward path
//   kEndReqDelay     TLM_UPDATED with END_REQ annotated `accept` later; BEGIN_RESP as above
//   kEarlyCompletion a read: TLM_UPDATED with BEGIN_RESP annotated `latency` later (then the
//                    initiator's END_RESP), unless a response awaits its END_RESP or is due; a
//                    write, or a read then: as kEndReqDelay
//   kCompleteAtOnce  TLM_COMPLETED annotated `latency` later
//   kArbiter         as DRAMSys's arbiter: TLM_ACCEPTED, END_REQ `accept` later and only then the
//                    next request; a BEGIN_RESP answered TLM_COMPLETED is not understood (the
//                    arbiter goes on only after END_RESP, on the return path or the forward path)
//   kLooselyTimed    b_transport only (annotated with `latency`), no nb_transport_fw: an LT memory
//   kLooselyTimedDmi the same, and grants DMI to the whole memory (read and write latency
//                    `latency`), hinting at it in every response
//   kLooselyTimedWaits b_transport that waits out the request's delay and `latency` (wait()) and
//                    returns a zero delay: a synchronising LT memory
//
// Each counts what it saw, so a test can tell that its style's path was taken, and the requests
// that came out of time order, which a target that trusts annotations (a PEQ) would mistime: a
// BEGIN_REQ (or b_transport call) timed before the previous one, or a BEGIN_REQ timed before the
// previous request's window ended (its END_REQ; a request answered with its response in the call
// was taken at its own time, as model/memory/tlm_checker.cpp reads the base protocol).
#pragma once

#include <tlm_utils/peq_with_get.h>
#include <tlm_utils/simple_target_socket.h>
#include <systemc>
#include <tlm>

#include <cstdint>
#include <cstring>
#include <deque>
#include <vector>

namespace rtsim::test {

enum class TargetStyle {
  kAcceptLater,
  kEndReqDelay,
  kEarlyCompletion,
  kCompleteAtOnce,
  kArbiter,
  kLooselyTimed,
  kLooselyTimedDmi,
  kLooselyTimedWaits
};

class StyledMemory : public sc_core::sc_module {
 public:
  tlm_utils::simple_target_socket<StyledMemory> socket;

  struct Counts {
    uint64_t requests = 0, end_resp_forward = 0, end_resp_returned = 0, completed_returned = 0;
    uint64_t b_transports = 0, dmi_grants = 0;
    uint64_t before_previous = 0;  // timed before the previous request (BEGIN_REQ or b_transport)
    uint64_t inside_window = 0;    // BEGIN_REQ timed before the previous request's END_REQ
  };

  SC_HAS_PROCESS(StyledMemory);
  StyledMemory(sc_core::sc_module_name name, TargetStyle style, std::vector<uint8_t> bytes,
               sc_core::sc_time latency, sc_core::sc_time accept)
      : sc_core::sc_module(name),
        socket("socket"),
        style_(style),
        bytes_(std::move(bytes)),
        latency_(latency),
        accept_(accept),
        accepting_("accepting"),
        due_("due") {
    if (loosely_timed()) {
      socket.register_b_transport(this, &StyledMemory::b_transport);
      if (style_ == TargetStyle::kLooselyTimedDmi)
        socket.register_get_direct_mem_ptr(this, &StyledMemory::get_direct_mem_ptr);
      return;  // simple_target_socket adapts nb_transport_fw to it, one transaction at a time
    }
    socket.register_nb_transport_fw(this, &StyledMemory::nb_transport_fw);
    SC_METHOD(end_request);
    sensitive << accepting_.get_event();
    dont_initialize();
    SC_METHOD(respond);
    sensitive << due_.get_event() << resume_;
    dont_initialize();
  }
  const Counts& counts() const { return counts_; }
  bool loosely_timed() const {
    return style_ == TargetStyle::kLooselyTimed || style_ == TargetStyle::kLooselyTimedDmi ||
           style_ == TargetStyle::kLooselyTimedWaits;
  }

 private:
  bool in_range(const tlm::tlm_generic_payload& p) const {
    return p.get_address() <= bytes_.size() &&
           bytes_.size() - p.get_address() >= p.get_data_length();
  }
  void take(tlm::tlm_generic_payload& p) {  // a write lands when the request is taken
    if (p.is_write())
      std::memcpy(bytes_.data() + p.get_address(), p.get_data_ptr(), p.get_data_length());
  }
  void answer(tlm::tlm_generic_payload& p) {  // a read copies when it is answered
    if (p.is_read())
      std::memcpy(p.get_data_ptr(), bytes_.data() + p.get_address(), p.get_data_length());
    p.set_response_status(tlm::TLM_OK_RESPONSE);
  }

  // A request timed at `at`, whose request channel is the target's until `until`.
  void check_order(sc_core::sc_time at, sc_core::sc_time until) {
    if (counts_.requests + counts_.b_transports > 1) {
      counts_.before_previous += at < last_request_;
      counts_.inside_window += at < window_end_;
    }
    last_request_ = at;
    window_end_ = until;
  }

  void b_transport(tlm::tlm_generic_payload& p, sc_core::sc_time& delay) {
    ++counts_.b_transports;
    check_order(sc_core::sc_time_stamp() + delay, sc_core::SC_ZERO_TIME);  // no request phase
    if (!in_range(p)) return p.set_response_status(tlm::TLM_ADDRESS_ERROR_RESPONSE);
    take(p);
    answer(p);
    if (style_ == TargetStyle::kLooselyTimedWaits) {
      sc_core::wait(delay + latency_);
      delay = sc_core::SC_ZERO_TIME;
      return;
    }
    delay += latency_;
    if (style_ == TargetStyle::kLooselyTimedDmi) p.set_dmi_allowed(true);
  }

  bool get_direct_mem_ptr(tlm::tlm_generic_payload&, tlm::tlm_dmi& d) {
    ++counts_.dmi_grants;
    d.set_dmi_ptr(bytes_.data());
    d.set_start_address(0);
    d.set_end_address(bytes_.size() - 1);
    d.allow_read_write();
    d.set_read_latency(latency_);
    d.set_write_latency(latency_);
    return true;
  }

  tlm::tlm_sync_enum nb_transport_fw(tlm::tlm_generic_payload& p, tlm::tlm_phase& phase,
                                     sc_core::sc_time& delay) {
    if (phase == tlm::END_RESP) {
      ++counts_.end_resp_forward;
      awaiting_end_resp_ = nullptr;
      resume_.notify(delay);
      return tlm::TLM_COMPLETED;
    }
    if (phase != tlm::BEGIN_REQ) return tlm::TLM_COMPLETED;
    ++counts_.requests;
    const sc_core::sc_time at = sc_core::sc_time_stamp() + delay;
    check_order(at, taken_at_once(p) ? at : at + accept_);
    if (!in_range(p)) {
      p.set_response_status(tlm::TLM_ADDRESS_ERROR_RESPONSE);
      return tlm::TLM_COMPLETED;
    }
    take(p);
    switch (style_) {
      case TargetStyle::kAcceptLater:
      case TargetStyle::kArbiter:
        p.acquire();
        accepting_.notify(p, delay + accept_);
        due_.notify(p, delay + latency_);
        ++due_count_;
        return tlm::TLM_ACCEPTED;
      case TargetStyle::kCompleteAtOnce:
        answer(p);
        delay += latency_;
        return tlm::TLM_COMPLETED;
      case TargetStyle::kEarlyCompletion:
        if (p.is_read() && !awaiting_end_resp_ && due_count_ == 0) {
          answer(p);
          delay += latency_;
          awaiting_end_resp_ = &p;
          phase = tlm::BEGIN_RESP;
          return tlm::TLM_UPDATED;
        }
        [[fallthrough]];
      default:  // kEndReqDelay
        p.acquire();
        due_.notify(p, delay + latency_);
        ++due_count_;
        delay += accept_;
        phase = tlm::END_REQ;
        return tlm::TLM_UPDATED;
    }
  }

  // Whether this BEGIN_REQ will be answered with its response in the call (no END_REQ window).
  bool taken_at_once(const tlm::tlm_generic_payload& p) const {
    return !in_range(p) || style_ == TargetStyle::kCompleteAtOnce ||
           (style_ == TargetStyle::kEarlyCompletion && p.is_read() && !awaiting_end_resp_ &&
            due_count_ == 0);
  }

  void end_request() {
    while (tlm::tlm_generic_payload* p = accepting_.get_next_transaction()) {
      tlm::tlm_phase phase = tlm::END_REQ;
      sc_core::sc_time t = sc_core::SC_ZERO_TIME;
      socket->nb_transport_bw(*p, phase, t);
    }
  }

  // Responses in time order, one at a time (response exclusion).
  void respond() {
    while (!awaiting_end_resp_) {
      tlm::tlm_generic_payload* p = due_.get_next_transaction();
      if (!p) return;
      --due_count_;
      answer(*p);
      tlm::tlm_phase phase = tlm::BEGIN_RESP;
      sc_core::sc_time t = sc_core::SC_ZERO_TIME;
      const tlm::tlm_sync_enum r = socket->nb_transport_bw(*p, phase, t);
      if (r == tlm::TLM_UPDATED && phase == tlm::END_RESP) {
        ++counts_.end_resp_returned;
      } else if (r == tlm::TLM_COMPLETED) {
        ++counts_.completed_returned;
        if (style_ == TargetStyle::kArbiter) awaiting_end_resp_ = p;  // waits for ever
      } else {
        awaiting_end_resp_ = p;  // TLM_ACCEPTED: END_RESP comes on the forward path
      }
      p->release();
    }
  }

  TargetStyle style_;
  std::vector<uint8_t> bytes_;
  sc_core::sc_time latency_, accept_;
  tlm_utils::peq_with_get<tlm::tlm_generic_payload> accepting_, due_;
  sc_core::sc_event resume_;
  const tlm::tlm_generic_payload* awaiting_end_resp_ = nullptr;
  uint64_t due_count_ = 0;  // accepted, response not sent yet
  sc_core::sc_time last_request_, window_end_;
  Counts counts_;
};

}  // namespace rtsim::test
