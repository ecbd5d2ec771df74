// The DRAM as a SystemC module: a thin wrapper that drives the DramController engine in
// simulated time and holds the simulated memory's bytes.
//
// fetch_line enqueues a read and returns kUnknown (DRAM times are decided by the scheduler). An
// activation on the scheduler's calendar advances the engine to the current time, and tells each
// requester through FillListener::on_fill at the first accelerator-clock edge at or after the
// data are ready (the DRAM runs on its own command clock; the accelerator samples on its own).
// Deliveries later than now wait in a small time-ordered queue. The module re-arms for the
// earliest of the engine's next event and the next delivery, so it costs no activation while idle. Needs sc_set_time_resolution(1, SC_PS).
//
// write_line is a posted write: the bytes are stored at once (functionally: a later line_data,
// and a read that completes later, see them, even a read enqueued before the write), and the
// write is queued in the engine for its timing only (it shares the FR-FCFS queue, the banks and
// the data bus with the reads). Nobody is told unless a listener is given.
//
// Backing store: the memory image (not copied) followed by `extra_bytes` of zeroed space (e.g. a
// frame buffer the accelerator writes after the image), addresses [0, image + extra_bytes).
// Writes are copy-on-write per page (max(4 KB, request_bytes), so no line straddles two pages):
// the first write to a page copies that page's image bytes (or zeros) into a page the module
// owns, and later reads and writes of the page use that copy. So the image costs nothing extra
// (copying it whole would double the peak memory a run reports, tens of MB for the paper's
// scenes), the store grows with what is written, and line_data is one array index: a written
// page, else the image, else a shared zero line.
//
// Line addresses are byte addresses of request_bytes-aligned blocks (the cache line above).
#pragma once

#include "model/dram_config.h"
#include "model/dram_controller.h"
#include "model/memory_interface.h"
#include "model/model_time.h"
#include "model/scheduler.h"
#include "model/stats_registry.h"

#include <systemc>

#include <cstdint>
#include <memory>
#include <queue>
#include <string>
#include <unordered_map>
#include <vector>

namespace rtsim::model {

class Dram : public sc_core::sc_module, public LineSource, public Scheduler::Client {
 public:
  // `memory` is the loaded memory image (may be null: with extra_bytes 0 that is a timing-only
  // model, whose line_data throws and whose accesses are not range-checked). It must outlive the
  // module and keep its size. `extra_bytes` of zeroed store follow the image.
  Dram(sc_core::sc_module_name name, const DramConfig& config, const std::vector<uint8_t>* memory,
       const Clock& accel_clock, uint64_t extra_bytes = 0);

  // Returns kUnknown; `listener->on_fill(line_addr, cookie, t)` follows at delivery time t
  // (`listener` may be null). `now` earlier than the simulation time is taken as now; a later
  // `now` (a requester's own latency already added) is honoured. `line_addr` must be
  // request_bytes-aligned (std::logic_error) and inside the store (std::out_of_range).
  Tick fetch_line(uint64_t line_addr, Tick now, FillListener* listener, uint64_t cookie) override;
  // Posted write of the request_bytes at `data` to the line at `line_addr` (aligned and inside
  // the store, as for fetch_line; `data` may be null only in a timing-only model). The bytes are
  // stored before this returns; the write then costs DRAM time like a read. If `listener` is
  // given, `listener->on_fill(line_addr, cookie, t)` is called at the first accelerator edge t at
  // or after the write's last data beat is in (last WR + WL + BL/2; tWR delays only the bank).
  void write_line(uint64_t line_addr, const uint8_t* data, Tick now, FillListener* listener = nullptr,
                  uint64_t cookie = 0);
  // The line's current bytes (written ones included); std::out_of_range if the line is not wholly
  // inside the store. Read it before the next write_line: a page's first write moves its lines
  // to the module's copy, and the old pointer then shows the image's bytes.
  const uint8_t* line_data(uint64_t line_addr) const override;
  // The channel a line maps to (a crossbar's destination port).
  uint32_t port_of(uint64_t line_addr) const override { return engine_.mapping().decode(line_addr).channel; }
  uint32_t port_count() const override { return engine_.config().channels; }

  uint64_t store_bytes() const { return store_bytes_; }  // image + extra_bytes
  uint64_t image_bytes() const { return image_bytes_; }
  uint64_t pages_written() const;                        // pages copied on write so far

  const DramController& engine() const { return engine_; }
  const DramStats& stats() const { return engine_.stats(); }
  void register_stats(StatsRegistry& registry, const std::string& prefix) const {
    engine_.register_stats(registry, prefix);
  }

 private:
  struct Requester {
    uint64_t line;
    FillListener* listener;
    uint64_t cookie;
  };
  struct Delivery {
    Tick when;
    uint64_t id;  // ids grow with enqueue order: ties deliver in request order
    bool operator>(const Delivery& o) const { return when != o.when ? when > o.when : id > o.id; }
  };

  void activate() override;  // on the scheduler's calendar
  void wake_for(Tick t);
  // If `aligned`, request_bytes-aligned (std::logic_error); if `in_store`, request_bytes from
  // line_addr fit in the store (std::out_of_range).
  void check_line(uint64_t line_addr, const char* what, bool aligned, bool in_store) const;
  uint8_t* writable_line(uint64_t line_addr);                   // copies its page on first write

  DramController engine_;
  const std::vector<uint8_t>* memory_;
  uint64_t image_bytes_ = 0;
  uint64_t store_bytes_ = 0;
  uint32_t page_shift_ = 0;
  std::vector<std::unique_ptr<uint8_t[]>> pages_;  // written pages, by address >> page_shift_
  std::vector<uint8_t> zero_line_;                 // an unwritten line of the extra space
  Clock accel_clock_;
  std::unordered_map<uint64_t, Requester> requesters_;  // by request id
  std::priority_queue<Delivery, std::vector<Delivery>, std::greater<Delivery>> deliveries_;
  std::vector<DramController::Completion> done_;  // scratch
  uint64_t next_id_ = 0;
};

}  // namespace rtsim::model
