#include "model/dram.h"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>

namespace rtsim::model {

namespace {

Tick sim_now_ps() { return Scheduler::instance().now(); }  // resolution is 1 ps

constexpr uint64_t kMinPageBytes = 4096;  // copy-on-write granularity (at least one line)

}  // namespace

Dram::Dram(sc_core::sc_module_name name, const DramConfig& config, const std::vector<uint8_t>* memory,
           const Clock& accel_clock, uint64_t extra_bytes)
    : sc_core::sc_module(name),
      engine_(config),
      memory_(memory),
      image_bytes_(memory ? memory->size() : 0),
      store_bytes_(image_bytes_ + extra_bytes),
      accel_clock_(accel_clock) {
  if (sc_core::sc_get_time_resolution() != sc_core::sc_time(1, sc_core::SC_PS))
    throw std::logic_error("Dram needs sc_set_time_resolution(1, SC_PS)");
  const uint64_t line = engine_.config().request_bytes;
  const uint64_t page = std::max<uint64_t>(kMinPageBytes, line);  // both powers of two
  while ((uint64_t(1) << page_shift_) < page) ++page_shift_;
  pages_.resize(size_t((store_bytes_ + page - 1) >> page_shift_));
  zero_line_.assign(line, 0);
  // A line across the image's end (an image whose size is not a multiple of request_bytes, with
  // extra space after it) is neither wholly image nor zeros: give its page a copy now.
  if (extra_bytes > 0 && image_bytes_ % line != 0) writable_line(image_bytes_ - image_bytes_ % line);
  Scheduler::instance().add(this);
}

void Dram::check_line(uint64_t line_addr, const char* what, bool aligned, bool in_store) const {
  const uint64_t bytes = engine_.config().request_bytes;
  if (aligned && line_addr % bytes != 0)
    throw std::logic_error(std::string("DRAM ") + what + ": address " + std::to_string(line_addr) +
                           " is not aligned to request_bytes (" + std::to_string(bytes) + ")");
  if (in_store && (line_addr > store_bytes_ || store_bytes_ - line_addr < bytes)) {
    char addr[24];
    std::snprintf(addr, sizeof addr, "0x%llx", static_cast<unsigned long long>(line_addr));
    std::string where = "the memory image (" + std::to_string(image_bytes_) + " bytes";
    if (store_bytes_ > image_bytes_) where += " + " + std::to_string(store_bytes_ - image_bytes_) + " bytes after it";
    throw std::out_of_range(std::string("DRAM line ") + addr + " (" + std::to_string(bytes) + " bytes) is outside " +
                            where + ")");
  }
}

Tick Dram::fetch_line(uint64_t line_addr, Tick now, FillListener* listener, uint64_t cookie) {
  const Tick sim_now = sim_now_ps();
  if (now < sim_now) now = sim_now;
  // A request outside the store is a caller's bug: fail here (a timing-only model has no store).
  check_line(line_addr, "fetch_line", true, store_bytes_ > 0);
  const uint64_t id = next_id_++;
  requesters_.emplace(id, Requester{line_addr, listener, cookie});
  engine_.enqueue(line_addr, now, id);
  wake_for(engine_.next_event_time());
  return kUnknown;
}

void Dram::write_line(uint64_t line_addr, const uint8_t* data, Tick now, FillListener* listener, uint64_t cookie) {
  const Tick sim_now = sim_now_ps();
  if (now < sim_now) now = sim_now;
  check_line(line_addr, "write_line", true, store_bytes_ > 0);
  if (store_bytes_ > 0) {
    if (!data) throw std::invalid_argument("DRAM write_line: no data for line " + std::to_string(line_addr));
    std::memcpy(writable_line(line_addr), data, engine_.config().request_bytes);
  }
  const uint64_t id = next_id_++;
  if (listener) requesters_.emplace(id, Requester{line_addr, listener, cookie});
  engine_.enqueue(line_addr, now, id, /*write=*/true);
  wake_for(engine_.next_event_time());
}

// Callers may ask for a finer-aligned address (an L1 line inside a larger request): the bytes
// from `line_addr` to the end of its request_bytes block are right, and that block never leaves
// its page.
const uint8_t* Dram::line_data(uint64_t line_addr) const {
  check_line(line_addr, "line_data", false, true);
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
    if (base < image_bytes_) std::memcpy(page.get(), memory_->data() + base, size_t(std::min(page_bytes, image_bytes_ - base)));
  }
  return page.get() + (line_addr - base);
}

uint64_t Dram::pages_written() const {
  uint64_t n = 0;
  for (const auto& p : pages_) n += p != nullptr;
  return n;
}

void Dram::activate() {
  const Tick now = sim_now_ps();
  done_.clear();
  engine_.advance(now, done_);
  for (const DramController::Completion& c : done_) {
    if (c.write && requesters_.find(c.id) == requesters_.end()) continue;  // posted, nobody to tell
    deliveries_.push(Delivery{accel_clock_.edge_at_or_after(c.data_ready), c.id});
  }
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
