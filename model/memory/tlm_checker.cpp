#include "model/memory/tlm_checker.h"

#include "model/sim/report.h"

#include <cinttypes>
#include <cstdio>

namespace rtsim::model {

namespace {

const char* phase_name(const tlm::tlm_phase& p) {
  if (p == tlm::BEGIN_REQ) return "BEGIN_REQ";
  if (p == tlm::END_REQ) return "END_REQ";
  if (p == tlm::BEGIN_RESP) return "BEGIN_RESP";
  if (p == tlm::END_RESP) return "END_RESP";
  return "an unknown phase";
}

}  // namespace

TlmChecker::TlmChecker(sc_core::sc_module_name name)
    : sc_core::sc_module(name),
      target_socket("target_socket"),
      initiator_socket("initiator_socket") {
  target_socket.register_nb_transport_fw(this, &TlmChecker::nb_transport_fw);
  target_socket.register_b_transport(this, &TlmChecker::b_transport);
  target_socket.register_transport_dbg(this, &TlmChecker::transport_dbg);
  target_socket.register_get_direct_mem_ptr(this, &TlmChecker::get_direct_mem_ptr);
  initiator_socket.register_nb_transport_bw(this, &TlmChecker::nb_transport_bw);
  initiator_socket.register_invalidate_direct_mem_ptr(this, &TlmChecker::invalidate_direct_mem_ptr);
}

void TlmChecker::violation(const tlm::tlm_generic_payload& p, const std::string& rule) const {
  char addr[24];
  std::snprintf(addr, sizeof addr, "0x%" PRIx64, uint64_t(p.get_address()));
  report_error(kReportTlm, std::string(name()) + ": " + rule + " (the " +
                               (p.is_write() ? "write" : "read") + " at " + addr + ", at " +
                               sc_core::sc_time_stamp().to_string() + ")");
}

void TlmChecker::check_request_fields(const tlm::tlm_generic_payload& p) {
  if (!p.is_read() && !p.is_write()) violation(p, "a request that is neither a read nor a write");
  if (!p.get_data_ptr() || p.get_data_length() == 0)
    violation(p, "a request without a data pointer or length");
  if (p.get_streaming_width() < p.get_data_length())
    violation(p, "a streaming width below the data length");
  if (p.get_response_status() != tlm::TLM_INCOMPLETE_RESPONSE)
    violation(p, "a request whose response status is not TLM_INCOMPLETE_RESPONSE");
}

void TlmChecker::check_response_status(const tlm::tlm_generic_payload& p, const char* how) {
  if (p.get_response_status() == tlm::TLM_INCOMPLETE_RESPONSE)
    violation(p, std::string("a response (") + how + ") with the status TLM_INCOMPLETE_RESPONSE");
}

void TlmChecker::begin(const tlm::tlm_generic_payload& p, Tick at) {
  ++stats_.transactions;
  ++stats_.phases;
  if (open_.count(&p)) violation(p, "BEGIN_REQ with a payload whose transaction has not ended");
  if (request_)
    violation(p, "BEGIN_REQ while another request awaits its END_REQ (request exclusion)");
  if (request_busy_.holds(at))
    violation(p, "BEGIN_REQ timed while the previous request was being taken (request exclusion)");
  check_request_fields(p);
  open_[&p] = {Phase::kBeginReq, at};
  request_ = &p;
}

void TlmChecker::transition(const tlm::tlm_generic_payload& p, const tlm::tlm_phase& phase, Tick at,
                            const char* how) {
  ++stats_.phases;
  const auto it = open_.find(&p);
  if (it == open_.end())
    violation(p, std::string(phase_name(phase)) + " (" + how + ") of no open transaction");
  Open& o = it->second;
  if (at < o.at)
    violation(p, std::string(phase_name(phase)) + " (" + how + ") before the last phase");
  if (phase == tlm::END_REQ) {
    if (o.phase != Phase::kBeginReq)
      violation(p, std::string("END_REQ (") + how + ") after END_REQ");
    request_ = nullptr;
    request_busy_ = {o.at, at};
    o = {Phase::kEndReq, at};
  } else if (phase == tlm::BEGIN_RESP) {
    if (o.phase == Phase::kBeginResp) violation(p, "a second BEGIN_RESP");
    if (response_)
      violation(p, "BEGIN_RESP while another response awaits its END_RESP (response exclusion)");
    if (response_busy_.holds(at))
      violation(
          p, "BEGIN_RESP timed while the previous response was being taken (response exclusion)");
    check_response_status(p, how);
    free_if_held(request_, request_busy_, p, o.at, at);  // stands for the missing END_REQ
    response_ = &p;
    o = {Phase::kBeginResp, at};
  } else if (phase == tlm::END_RESP) {
    if (o.phase != Phase::kBeginResp)
      violation(p, std::string("END_RESP (") + how + ") before BEGIN_RESP");
    complete(p, at, how);
  } else {
    violation(p, std::string("BEGIN_REQ (") + how + ") of an open transaction");
  }
}

void TlmChecker::free_if_held(const tlm::tlm_generic_payload*& holder, Window& busy,
                              const tlm::tlm_generic_payload& p, Tick from, Tick at) {
  if (holder != &p) return;
  holder = nullptr;
  busy = {from, at};
}

void TlmChecker::complete(const tlm::tlm_generic_payload& p, Tick at, const char* how) {
  const auto it = open_.find(&p);
  if (it == open_.end())
    violation(p, std::string("TLM_COMPLETED (") + how + ") of no open transaction");
  if (at < it->second.at) violation(p, std::string("the end (") + how + ") before the last phase");
  check_response_status(p, how);
  free_if_held(request_, request_busy_, p, it->second.at, at);
  free_if_held(response_, response_busy_, p, it->second.at, at);
  open_.erase(it);
}

void TlmChecker::returned(const tlm::tlm_generic_payload& p, tlm::tlm_sync_enum r,
                          const tlm::tlm_phase& before, const tlm::tlm_phase& after, Tick at,
                          const char* path) {
  switch (r) {
    case tlm::TLM_ACCEPTED:
      if (after != before)
        violation(p, std::string("TLM_ACCEPTED on the ") + path + " path with the phase changed");
      break;
    case tlm::TLM_UPDATED:
      if (after == before)
        violation(p, std::string("TLM_UPDATED on the ") + path + " path with the phase unchanged");
      transition(p, after, at, "a return value");
      break;
    case tlm::TLM_COMPLETED: complete(p, at, "a return value"); break;
  }
}

tlm::tlm_sync_enum TlmChecker::nb_transport_fw(tlm::tlm_generic_payload& p, tlm::tlm_phase& phase,
                                               sc_core::sc_time& delay) {
  const tlm::tlm_phase before = phase;
  const Tick at = time_of(delay);
  if (phase == tlm::BEGIN_REQ)
    begin(p, at);
  else if (phase == tlm::END_RESP)
    transition(p, phase, at, "the forward path");
  else
    violation(p, std::string(phase_name(phase)) + " on the forward path");
  const tlm::tlm_sync_enum r = initiator_socket->nb_transport_fw(p, phase, delay);
  if (before == tlm::END_RESP) {
    if (r != tlm::TLM_COMPLETED) violation(p, "END_RESP not answered with TLM_COMPLETED");
    return r;
  }
  returned(p, r, before, phase, time_of(delay), "return");
  // A request answered with its response in the call was taken at its own time: the delay times
  // the response, not the request channel.
  if (r != tlm::TLM_ACCEPTED && phase != tlm::END_REQ) request_busy_ = {at, at};
  return r;
}

tlm::tlm_sync_enum TlmChecker::nb_transport_bw(tlm::tlm_generic_payload& p, tlm::tlm_phase& phase,
                                               sc_core::sc_time& delay) {
  const tlm::tlm_phase before = phase;
  const Tick at = time_of(delay);
  if (phase == tlm::END_REQ || phase == tlm::BEGIN_RESP)
    transition(p, phase, at, "the backward path");
  else
    violation(p, std::string(phase_name(phase)) + " on the backward path");
  const tlm::tlm_sync_enum r = target_socket->nb_transport_bw(p, phase, delay);
  if (before == tlm::END_REQ) {
    if (r != tlm::TLM_ACCEPTED) violation(p, "END_REQ not answered with TLM_ACCEPTED");
    return r;
  }
  returned(p, r, before, phase, time_of(delay), "backward");
  return r;
}

void TlmChecker::b_transport(tlm::tlm_generic_payload& p, sc_core::sc_time& delay) {
  ++stats_.transactions;
  if (open_.count(&p)) violation(p, "b_transport with a payload whose transaction has not ended");
  check_request_fields(p);
  initiator_socket->b_transport(p, delay);
  check_response_status(p, "b_transport");
}

unsigned TlmChecker::transport_dbg(tlm::tlm_generic_payload& p) {
  return initiator_socket->transport_dbg(p);
}

bool TlmChecker::get_direct_mem_ptr(tlm::tlm_generic_payload& p, tlm::tlm_dmi& dmi) {
  return initiator_socket->get_direct_mem_ptr(p, dmi);
}

void TlmChecker::invalidate_direct_mem_ptr(sc_dt::uint64 start, sc_dt::uint64 end) {
  target_socket->invalidate_direct_mem_ptr(start, end);
}

void TlmChecker::register_stats(StatsRegistry& r, const std::string& prefix) const {
  StatsRegistrar v(r, prefix);
  describe_stats(v, stats_);
}

}  // namespace rtsim::model
