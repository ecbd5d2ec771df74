#include "model/memory/memory_port.h"

#include "model/sim/report.h"

#include <cinttypes>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <utility>

namespace rtsim::model {

struct MemoryPort::Transaction : tlm::tlm_generic_payload {
  explicit Transaction(tlm::tlm_mm_interface* mm, uint32_t bytes)
      : tlm::tlm_generic_payload(mm), data(bytes) {}
  std::vector<uint8_t> data;
  uint64_t line = 0;
  Tick requested = 0;  // when it reaches memory
  bool write = false;
  FillListener* listener = nullptr;
  uint64_t cookie = 0;
  uint64_t order = 0;     // requests made before it
  std::string initiator;  // writes: who wrote
};

MemoryPort::MemoryPort(sc_core::sc_module_name name, uint32_t line_bytes, const DramConfig& mapping,
                       const Clock& clock, Calendar& calendar, PortTarget target)
    : sc_core::sc_module(name),
      socket("socket"),
      line_bytes_(line_bytes),
      channels_(mapping.channels),
      mapping_(mapping.address_mapping, mapping.channels),
      clock_(clock),
      calendar_(calendar),
      in_time_order_(target != PortTarget::kOwnCalendar) {
  socket.register_nb_transport_bw(this, &MemoryPort::nb_transport_bw);
  socket.register_invalidate_direct_mem_ptr(this, &MemoryPort::invalidate_direct_mem_ptr);
  if (target == PortTarget::kLooselyTimed)
    lt_ = std::make_unique<LooselyTimedPath>(
        basename(), [this] { return socket.operator->(); },
        [this](tlm::tlm_generic_payload& p, Tick at) {
          response(static_cast<Transaction*>(&p), at, false);
        });
  calendar_.add(this, clock_.period());
}

MemoryPort::~MemoryPort() = default;

MemoryPort::Transaction* MemoryPort::make(uint64_t line, Tick arrival, bool write) {
  if (free_.empty()) {
    all_.push_back(std::make_unique<Transaction>(this, line_bytes_));
    free_.push_back(all_.back().get());
  }
  Transaction* t = free_.back();
  free_.pop_back();
  t->set_command(write ? tlm::TLM_WRITE_COMMAND : tlm::TLM_READ_COMMAND);
  t->set_address(line);
  t->set_data_ptr(t->data.data());
  t->set_data_length(line_bytes_);
  t->set_streaming_width(line_bytes_);
  t->set_byte_enable_ptr(nullptr);
  t->set_dmi_allowed(false);
  t->set_response_status(tlm::TLM_INCOMPLETE_RESPONSE);
  t->line = line;
  t->requested = arrival;
  t->write = write;
  t->listener = nullptr;
  t->cookie = 0;
  t->order = requests_made_++;
  t->acquire();
  return t;
}

void MemoryPort::free(tlm::tlm_generic_payload* p) {
  p->reset();  // drops extensions a target may have set
  free_.push_back(static_cast<Transaction*>(p));
}

Tick MemoryPort::fetch_line(uint64_t line_addr, Tick now, FillListener* listener, uint64_t cookie) {
  Transaction* t = make(line_addr, std::max(now, calendar_.now()), false);
  t->listener = listener;
  t->cookie = cookie;
  ++stats_.reads;
  send(t);
  return kUnknown;
}

void MemoryPort::write_line(uint64_t line_addr, const uint8_t* data, Tick now,
                            const std::string& initiator, FillListener* listener, uint64_t cookie) {
  Transaction* t = make(line_addr, std::max(now, calendar_.now()), true);
  std::memcpy(t->data.data(), data, line_bytes_);
  t->initiator = initiator;
  t->listener = listener;
  t->cookie = cookie;
  ++stats_.writes;
  send(t);
}

void MemoryPort::send(Transaction* t) {
  // A platform's memory gets its requests in time order (issue 39): they are made in calendar
  // order, but each reaches memory its requester's latency later, so one made later may arrive
  // earlier. Each waits here until the calendar reaches its arrival (none is made for a time
  // before the calendar's now). Our GDDR3 orders them by arrival itself: due when made.
  const Tick now = calendar_.now();
  const Tick due = in_time_order_ ? t->requested : now;
  if (!open_ && requests_.empty() && due <= now) return send_now(t, due);
  requests_.push({due, t->order, t});
  // (an open request's END_REQ, or an activation already armed for the requests ahead, sends it)
  if (in_time_order_ && !open_) calendar_.schedule(this, due);
}

void MemoryPort::send_due() {
  const Tick now = calendar_.now();
  while (!open_ && !requests_.empty() && requests_.top().when <= now) {
    const Queued q = requests_.top();
    requests_.pop();
    send_now(q.t, q.when);
  }
  if (!open_ && !requests_.empty()) calendar_.schedule(this, requests_.top().when);
}

void MemoryPort::send_now(Transaction* t, Tick due) {
  const Tick now = calendar_.now();
  const TimeBase& time = calendar_.time();
  if (now > due) ++stats_.refused;  // it waited for the request channel
  Tick at = std::max(t->requested, now);
  if (lt_) return lt_->send(*t, now, at, time);  // no phases, no exclusion rules
  // The request channel: not before the target has taken the previous request. In time order
  // that window began at or before `at`; our GDDR3 may get a request timed before it.
  if (in_time_order_)
    at = std::max(at, taking_.until);
  else if (at >= taking_.from && at < taking_.until)
    at = taking_.until;
  tlm::tlm_phase phase = tlm::BEGIN_REQ;
  sc_core::sc_time delay = time.to_sc_time(at - now);
  // Open before the call: a target may send END_REQ or BEGIN_RESP back inside it.
  open_ = t;
  open_at_ = at;
  sending_ = true;
  const tlm::tlm_sync_enum r = socket->nb_transport_fw(*t, phase, delay);
  sending_ = false;
  const Tick then = now + time.to_tick(delay);
  if (r == tlm::TLM_ACCEPTED) return;  // END_REQ comes later (or came inside the call)
  open_ = nullptr;
  if (r == tlm::TLM_UPDATED && phase == tlm::END_REQ) {
    taking_ = {at, then};
    return;
  }
  // Answered with its response: taken at its own time (the delay times the response).
  taking_ = {at, at};
  if (r == tlm::TLM_UPDATED && phase != tlm::BEGIN_RESP)
    report_error(kReportTlm, std::string(name()) + ": BEGIN_REQ answered TLM_UPDATED with " +
                                 phase.get_name() + " (END_REQ or BEGIN_RESP expected)");
  // Early completion (TLM_UPDATED with BEGIN_RESP) is answered with END_RESP at the response's
  // time, as Accellera's adapters do; TLM_COMPLETED needs nothing more. Either way the response
  // is queued, never delivered inside the requester's fetch_line.
  if (r == tlm::TLM_UPDATED) {
    phase = tlm::END_RESP;
    sending_ = true;
    const tlm::tlm_sync_enum ended = socket->nb_transport_fw(*t, phase, delay);
    sending_ = false;
    if (ended != tlm::TLM_COMPLETED)
      report_error(kReportTlm, std::string(name()) + ": END_RESP not answered TLM_COMPLETED");
  }
  response(t, then, false);
}

tlm::tlm_sync_enum MemoryPort::nb_transport_bw(tlm::tlm_generic_payload& p, tlm::tlm_phase& phase,
                                               sc_core::sc_time& delay) {
  const Tick at = calendar_.now() + calendar_.time().to_tick(delay);
  // END_REQ, or a response to the open request (the base protocol's implicit END_REQ), frees the
  // request channel from its time on.
  if (&p == open_ && (phase == tlm::END_REQ || phase == tlm::BEGIN_RESP)) {
    if (phase == tlm::BEGIN_RESP) warn_serialised();
    open_ = nullptr;
    taking_ = {open_at_, at};
    if (!requests_.empty())
      calendar_.schedule(this, std::max(clock_.edge_at_or_after(at), requests_.top().when));
  }
  if (phase != tlm::BEGIN_RESP) return tlm::TLM_ACCEPTED;
  response(static_cast<Transaction*>(&p), at, true);
  // Taken at once (it waits here for its clock edge): END_RESP at the response's time, which a
  // target that waits for END_RESP before its next response (DRAMSys's arbiter) needs.
  phase = tlm::END_RESP;
  return tlm::TLM_UPDATED;
}

// Accellera's nb-to-b adapter (simple_target_socket on a target that registered only
// b_transport) ends each request with its response: the model then runs one access at a time, ~19x
// slower on the city (docs/systemc-integration.md), with nothing else to show for it.
void MemoryPort::warn_serialised() {
  if (std::exchange(warned_serialised_, true)) return;
  report_warning(
      kReportSerialised,
      std::string(name()) +
          ": the memory ended a request only with its response (BEGIN_RESP with no END_REQ), as "
          "simple_target_socket's nb-to-b adapter does for a target with only b_transport; while "
          "it does so, requests are serialised (one transaction at a time), so the frame's cycles "
          "include every access's full latency back to back. Attach a loosely-timed memory with "
          "MemoryTarget::kLooselyTimed: its calls overlap (docs/systemc-integration.md, "
          "\"Loosely-timed memories\"). Reported once.");
}

void MemoryPort::invalidate_direct_mem_ptr(sc_dt::uint64 start, sc_dt::uint64 end) {
  if (lt_) lt_->invalidate(start, end);
}

void MemoryPort::response(Transaction* t, Tick at, bool may_deliver_now) {
  if (!t->is_response_ok()) failed(*t);
  ++stats_.responses;
  if (drained_ && in_flight() == 0) drained_();
  if (t->write) trace(*t, at);
  if (t->write && !t->listener) {  // posted, and nobody counts its acknowledgement
    t->release();
    return;
  }
  // From a block of this calendar's (not from a target answering inside our own call, which may
  // come from a requester's fetch_line)
  const bool ours = may_deliver_now && calendar_.running() && !sending_;
  Tick edge = clock_.edge_at_or_after(at);
  if (ours && edge == calendar_.now() && responses_.empty()) {
    // Our GDDR3's, at an edge: already in the fixed order
    deliver(t);
    return;
  }
  // The platform's responses are registered: taken at the first edge after their time. SystemC
  // does not order the processes of one time, so taking one at its own edge would make the
  // figures depend on whether the calendar had run yet.
  if (!ours && edge == at) edge += clock_.period();
  responses_.push({edge, t->order, t});
  calendar_.schedule(this, edge);
}

void MemoryPort::deliver(Transaction* t) {
  const Tick now = calendar_.now();
  if (!t->write) {
    stats_.latency_cycles += clock_.ceil_cycles(now - t->requested);
    trace(*t, now);
  }
  const Transaction* outer = delivering_;
  delivering_ = t;
  if (t->listener) t->listener->on_fill(t->line, t->cookie, now);
  delivering_ = outer;
  t->release();
}

void MemoryPort::activate() {
  const Tick now = calendar_.now();
  while (!responses_.empty() && responses_.top().when <= now) {
    Transaction* t = responses_.top().t;
    responses_.pop();
    deliver(t);
  }
  send_due();
  if (!responses_.empty()) calendar_.schedule(this, responses_.top().when);
}

const uint8_t* MemoryPort::line_data(uint64_t line_addr) const {
  const uint64_t block = line_addr & ~uint64_t(line_bytes_ - 1);
  if (!delivering_ || delivering_->line != block)  // the caches keep what they hand on
    report_error(kReportInternal, std::string(name()) + ": line " + std::to_string(block) +
                                      " asked for outside its response");
  return delivering_->data.data() + (line_addr - block);
}

void MemoryPort::name_requester(const FillListener* listener, const std::string& name) {
  names_.push_back({listener, name});
}

void MemoryPort::failed(const Transaction& t) const {
  char addr[24];
  std::snprintf(addr, sizeof addr, "0x%" PRIx64, t.line);
  report_error(kReportMemory, std::string(name()) + ": " + (t.write ? "write" : "read") + " of " +
                                  std::to_string(line_bytes_) + " bytes at " + addr +
                                  " failed: " + t.get_response_string());
}

void MemoryPort::open_trace(const TraceRequest& request) {
  trace_request_ = request;
  trace_ = std::make_unique<std::ofstream>(request.file + ".part");
  if (!*trace_) report_error(kReportTrace, "cannot write " + request.file);
  *trace_ << "cycle,initiator,address,bytes,op,latency_cycles\n";
}

void MemoryPort::close_trace() {
  if (!trace_) return;
  trace_->close();
  const bool ok = !trace_->fail();
  trace_.reset();
  std::error_code ec;
  if (ok) std::filesystem::rename(trace_request_.file + ".part", trace_request_.file, ec);
  if (!ok || ec) {
    std::filesystem::remove(trace_request_.file + ".part", ec);
    report_error(kReportTrace, "cannot write " + trace_request_.file);
  }
}

void MemoryPort::trace(const Transaction& t, Tick done) {
  if (!trace_) return;
  const uint64_t cycle = clock_.to_cycles(t.requested);
  if (cycle < trace_request_.start_cycle || cycle >= trace_request_.end_cycle) return;
  const std::string* who = &t.initiator;
  static const std::string unknown = "?";
  if (!t.write) {
    who = &unknown;
    for (const auto& [l, n] : names_)
      if (l == t.listener) who = &n;
  }
  char addr[24];
  std::snprintf(addr, sizeof addr, "0x%" PRIx64, t.line);
  *trace_ << cycle << ',' << *who << ',' << addr << ',' << line_bytes_ << ','
          << (t.write ? 'W' : 'R') << ','
          << clock_.ceil_cycles(done > t.requested ? done - t.requested : 0) << '\n';
}

void MemoryPort::register_stats(StatsRegistry& r, const std::string& prefix) const {
  StatsRegistrar v(r, prefix);
  describe_stats(v, stats_);
  if (lt_) lt_->register_stats(r, prefix);
}

}  // namespace rtsim::model
