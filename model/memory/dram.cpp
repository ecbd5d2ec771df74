#include "model/memory/dram.h"

#include "model/sim/report.h"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>
#include <utility>

namespace rtsim::model {

namespace {

constexpr uint64_t kMinPageBytes = 4096;  // copy-on-write granularity (at least one line)

}  // namespace

Dram::Dram(sc_core::sc_module_name name, const DramConfig& config,
           const std::vector<uint8_t>* memory, const Clock& accel_clock, Calendar& calendar,
           uint64_t extra_bytes)
    : sc_core::sc_module(name),
      socket("socket"),
      host_socket("host_socket"),
      calendar_(calendar),
      engine_(config),
      memory_(memory),
      image_bytes_(memory ? memory->size() : 0),
      store_bytes_(image_bytes_ + extra_bytes),
      accel_clock_(accel_clock) {
  const uint64_t line = engine_.config().request_bytes;
  const uint64_t page = std::max<uint64_t>(kMinPageBytes, line);  // both powers of two
  while ((uint64_t(1) << page_shift_) < page) ++page_shift_;
  pages_.resize(size_t((store_bytes_ + page - 1) >> page_shift_));
  zero_line_.assign(line, 0);
  // A line across the image's end (an image whose size is not a multiple of request_bytes, with
  // extra space after it) is neither wholly image nor zeros: give its page a copy now.
  if (extra_bytes > 0 && image_bytes_ % line != 0)
    writable_line(image_bytes_ - image_bytes_ % line);
  socket.register_nb_transport_fw(this, &Dram::nb_transport_fw);
  host_socket.register_b_transport(this, &Dram::host_b_transport);
  host_socket.register_transport_dbg(this, &Dram::host_transport_dbg);
  calendar_.add(this);
}

tlm::tlm_response_status Dram::check(const tlm::tlm_generic_payload& p) const {
  const uint64_t bytes = engine_.config().request_bytes;
  if (p.get_data_length() != bytes || p.get_streaming_width() < bytes || p.get_byte_enable_ptr())
    return tlm::TLM_BURST_ERROR_RESPONSE;
  if (p.get_address() % bytes != 0 || (store_bytes_ > 0 && !in_store(p.get_address())))
    return tlm::TLM_ADDRESS_ERROR_RESPONSE;
  return tlm::TLM_OK_RESPONSE;
}

tlm::tlm_sync_enum Dram::nb_transport_fw(tlm::tlm_generic_payload& p, tlm::tlm_phase& phase,
                                         sc_core::sc_time& delay) {
  if (phase == tlm::END_RESP) {      // the held-back responses may go
    if (&p == awaiting_end_resp_) {  // the next response, not before this END_RESP's time
      awaiting_end_resp_ = nullptr;
      calendar_.schedule(this, calendar_.now() + calendar_.time().to_tick(delay));
    }
    return tlm::TLM_COMPLETED;
  }
  if (phase != tlm::BEGIN_REQ) return tlm::TLM_COMPLETED;
  const tlm::tlm_response_status status = check(p);
  if (status != tlm::TLM_OK_RESPONSE) {
    p.set_response_status(status);
    return tlm::TLM_COMPLETED;
  }
  const Tick arrival = calendar_.now() + calendar_.time().to_tick(delay);
  if (!engine_.accepts(p.get_address())) {
    // Its channel is full: END_REQ when the channel has room (activate)
    if (held_back_)
      report_error(kReportTlm, std::string(name()) + ": BEGIN_REQ before the END_REQ of the last");
    held_back_ = &p;
    held_back_arrival_ = arrival;
    ++target_stats_.held_back;
    return tlm::TLM_ACCEPTED;
  }
  accept(p, arrival);
  phase = tlm::END_REQ;
  return tlm::TLM_UPDATED;
}

void Dram::accept(tlm::tlm_generic_payload& p, Tick arrival) {
  const uint64_t line = p.get_address();
  const bool write = p.is_write();
  if (write && store_bytes_ > 0)
    std::memcpy(writable_line(line), p.get_data_ptr(), engine_.config().request_bytes);
  if (!write && store_bytes_ > 0 && in_store(line)) {
    // The bytes are copied out at the delivery, many events from now: ask the host for them now,
    // or the copy waits on the host's memory (a frame's incoherent rays reach all of a scene)
    const uint8_t* bytes = line_data(line);
    __builtin_prefetch(bytes);
    __builtin_prefetch(bytes + engine_.config().request_bytes - 1);
  }
  const uint64_t id = next_id_++;
  requesters_.emplace(id, Requester{line, &p});
  engine_.enqueue(line, arrival, id, write);
  wake_for(engine_.next_event_time());
}

void Dram::register_stats(StatsRegistry& registry, const std::string& prefix) const {
  engine_.register_stats(registry, prefix);
  StatsRegistrar v(registry, prefix);
  if (engine_.config().input_queue > 0) describe_stats(v, target_stats_);
}

void Dram::respond(tlm::tlm_generic_payload& p) {
  p.set_response_status(tlm::TLM_OK_RESPONSE);
  tlm::tlm_phase phase = tlm::BEGIN_RESP;
  sc_core::sc_time t = sc_core::SC_ZERO_TIME;
  // TLM_ACCEPTED: the next response waits for this one's END_RESP (response exclusion), which may
  // also come inside the call
  awaiting_end_resp_ = &p;
  if (socket->nb_transport_bw(p, phase, t) != tlm::TLM_ACCEPTED && awaiting_end_resp_ == &p)
    awaiting_end_resp_ = nullptr;
}

// Callers may ask for a finer-aligned address (an L1 line inside a larger request): the bytes
// from `line_addr` to the end of its request_bytes block are right, and that block never leaves
// its page.
const uint8_t* Dram::line_data(uint64_t line_addr) const {
  if (!in_store(line_addr)) {
    char addr[24];
    std::snprintf(addr, sizeof addr, "0x%llx", static_cast<unsigned long long>(line_addr));
    std::string where = "the memory image (" + std::to_string(image_bytes_) + " bytes";
    if (store_bytes_ > image_bytes_)
      where += " + " + std::to_string(store_bytes_ - image_bytes_) + " bytes after it";
    report_error(kReportMemory, std::string(name()) + ": line " + addr + " (" +
                                    std::to_string(engine_.config().request_bytes) +
                                    " bytes) is outside " + where + ")");
  }
  const uint64_t bytes = engine_.config().request_bytes;
  if (const std::unique_ptr<uint8_t[]>& page = pages_[size_t(line_addr >> page_shift_)])
    return page.get() + (line_addr & ((uint64_t(1) << page_shift_) - 1));
  const uint64_t block = line_addr & ~(bytes - 1);
  if (block + bytes <= image_bytes_) return memory_->data() + line_addr;
  return zero_line_.data() + (line_addr - block);  // unwritten extra space (a block across the
                                                   // image's end has its page copied)
}

uint8_t* Dram::writable_line(uint64_t line_addr) {
  const uint64_t page_bytes = uint64_t(1) << page_shift_;
  const uint64_t base = line_addr & ~(page_bytes - 1);
  std::unique_ptr<uint8_t[]>& page = pages_[size_t(base >> page_shift_)];
  if (!page) {
    page = std::make_unique<uint8_t[]>(size_t(page_bytes));  // zeroed
    if (base < image_bytes_)
      std::memcpy(page.get(), memory_->data() + base,
                  size_t(std::min(page_bytes, image_bytes_ - base)));
  }
  return page.get() + (line_addr - base);
}

unsigned int Dram::host_transport_dbg(tlm::tlm_generic_payload& p) {
  const uint64_t addr = p.get_address(), n = p.get_data_length();
  if (p.get_byte_enable_ptr() || addr > store_bytes_ || n > store_bytes_ - addr) return 0;
  const uint64_t line_bytes = engine_.config().request_bytes;
  uint8_t* data = p.get_data_ptr();
  for (uint64_t at = addr; at < addr + n;) {
    const uint64_t line = at / line_bytes * line_bytes;
    const uint64_t k = std::min(line + line_bytes, addr + n) - at;
    if (p.is_write())
      std::memcpy(writable_line(line) + (at - line), data + (at - addr), k);
    else
      std::memcpy(data + (at - addr), line_data(line) + (at - line), k);
    at += k;
  }
  return unsigned(n);
}

void Dram::host_b_transport(tlm::tlm_generic_payload& p, sc_core::sc_time&) {
  if (p.get_byte_enable_ptr() || p.get_streaming_width() < p.get_data_length())
    return p.set_response_status(tlm::TLM_BURST_ERROR_RESPONSE);
  if (!p.is_read() && !p.is_write()) return p.set_response_status(tlm::TLM_COMMAND_ERROR_RESPONSE);
  const bool inside = host_transport_dbg(p) == p.get_data_length() || p.get_data_length() == 0;
  p.set_response_status(inside ? tlm::TLM_OK_RESPONSE : tlm::TLM_ADDRESS_ERROR_RESPONSE);
}

uint64_t Dram::pages_written() const {
  uint64_t n = 0;
  for (const auto& p : pages_) n += p != nullptr;
  return n;
}

void Dram::activate() {
  const Tick now = calendar_.now();
  done_.clear();
  engine_.advance(now, done_);
  if (commands_) commands_->drain_if_full();
  if (held_back_ && engine_.accepts(held_back_->get_address())) {
    // Taken now, or when it reaches memory if that is later (the END_REQ's time)
    tlm::tlm_generic_payload& p = *std::exchange(held_back_, nullptr);
    const Tick at = std::max(held_back_arrival_, now);
    accept(p, at);
    tlm::tlm_phase phase = tlm::END_REQ;
    sc_core::sc_time t = calendar_.time().to_sc_time(at - now);
    socket->nb_transport_bw(p, phase, t);
  }
  // A read's data go at the accelerator's edge after they are in; a write (posted: nobody waits
  // for it) is answered when its data are in.
  for (const DramController::Completion& c : done_)
    deliveries_.push(
        Delivery{c.write ? c.data_ready : accel_clock_.edge_at_or_after(c.data_ready), c.id});
  while (!awaiting_end_resp_ && !deliveries_.empty() && deliveries_.top().when <= now) {
    const Delivery d = deliveries_.top();
    deliveries_.pop();
    const auto it = requesters_.find(d.id);
    const Requester r = it->second;
    requesters_.erase(it);
    // The bytes as they are now (writes posted before this moment included).
    if (store_bytes_ > 0 && r.payload->is_read())
      std::memcpy(r.payload->get_data_ptr(), line_data(r.line), engine_.config().request_bytes);
    respond(*r.payload);
  }
  Tick next = engine_.next_event_time();
  if (!deliveries_.empty() && !awaiting_end_resp_) next = std::min(next, deliveries_.top().when);
  wake_for(next);
}

void Dram::open_command_trace(const TraceRequest& request) {
  commands_ = std::make_unique<DramCommandTrace>(request, accel_clock_);
  engine_.set_command_trace(commands_->buffer());
}

void Dram::close_command_trace() {
  if (!commands_) return;
  engine_.set_command_trace(nullptr);
  commands_->close();
}

void Dram::wake_for(Tick t) {
  if (t != kUnknown) calendar_.schedule(this, t);  // a pending earlier time stands
}

}  // namespace rtsim::model
