// The GDDR3 memory as a SystemC module and a TLM-2.0 target (`socket`, approximately-timed base
// protocol): a thin wrapper that drives the DramController engine in simulated time and holds the
// simulated memory's bytes. It acts on the calendar, at its command clock's exact times whatever
// SystemC's resolution (model/sim/calendar.h).
//
// A read (BEGIN_REQ, its delay annotation = when it reaches memory) is accepted at once
// (TLM_UPDATED, END_REQ) and enqueued in the engine when its channel has room; when the channel's
// input queue is full (DramConfig::input_queue) it is held back (TLM_ACCEPTED) and END_REQ goes
// on the backward path at the activation that finds room, the base protocol's backpressure: the
// initiator sends nothing more until then.
// An activation on the calendar advances the engine to the current time; a read's response
// (BEGIN_RESP, with the line's bytes) goes at the first accelerator-clock edge at or after its
// data are ready (the DRAM runs on its own command clock; the accelerator samples on its own).
// Responses later than now wait in a small time-ordered queue, sent in (time, request order), one
// at a time: an initiator that answers a BEGIN_RESP with TLM_ACCEPTED holds the next until its
// END_RESP (the response exclusion rule; requests are never refused). The module re-arms for the
// earliest of the engine's next event and the next response, so it costs no activation while idle.
//
// A write is posted: its bytes are stored at once (functionally: a later read sees them, even one
// enqueued before the write) and the write is queued in the engine for its timing only (it shares
// the FR-FCFS queue, the banks and the data bus with the reads); its response goes at the time
// the engine reports its last data beat in. A request that is not one whole
// line inside the store completes at once with an address or burst error. `socket` has no debug
// transport: nothing of the model needs one (docs/systemc-integration.md), so every golden setup
// runs on a target without it; line_data() shows the store to a test or a debugger, and
// `host_socket` to a platform.
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

#include "model/memory/dram_command_trace.h"
#include "model/memory/dram_config.h"
#include "model/memory/dram_controller.h"
#include "model/memory/line_source.h"
#include "model/sim/calendar.h"
#include "model/sim/stats_registry.h"
#include "model/sim/time.h"

#include <tlm_utils/simple_target_socket.h>
#include <systemc>
#include <tlm>

#include <cstdint>
#include <memory>
#include <queue>
#include <string>
#include <unordered_map>
#include <vector>

namespace rtsim::model {

// The calendar's side first, as for Unit (model/sim/unit.h).
// What the TLM-2.0 target adds to the timing engine's figures.
struct DramTargetStats {
  uint64_t held_back = 0;
};

// Every DramTargetStats field, once (model/sim/stats_description.h); only with an input queue.
template <class V>
void describe_stats(V& v, const DramTargetStats& s) {
  v.counter("held_back", s.held_back, "count",
            "requests whose channel's input queue was full (END_REQ waited)");
}

class Dram : public Calendar::Client, public sc_core::sc_module {
 public:
  tlm_utils::simple_target_socket<Dram> socket;
  // The platform's way in (a host bus window onto the memory, as a PCIe BAR onto a GPU's): any
  // byte range inside the store, read or written at once with b_transport or transport_dbg. It
  // takes no time and leaves the DRAM's state alone: a platform loads the image before a frame.
  tlm_utils::simple_target_socket_optional<Dram> host_socket;

  // `memory` is the loaded memory image (may be null: with extra_bytes 0 that is a timing-only
  // model, whose line_data reports an error and whose accesses are not range-checked). It must
  // outlive the module and keep its size. `extra_bytes` of zeroed store follow the image.
  Dram(sc_core::sc_module_name name, const DramConfig& config, const std::vector<uint8_t>* memory,
       const Clock& accel_clock, Calendar& calendar, uint64_t extra_bytes = 0);

  // The line's current bytes (written ones included); rtsim/memory if the line is not wholly
  // inside the store. Read it before the next write: a page's first write moves its lines to the
  // module's copy, and the old pointer then shows the image's bytes.
  const uint8_t* line_data(uint64_t line_addr) const;

  uint64_t store_bytes() const { return store_bytes_; }  // image + extra_bytes
  uint64_t image_bytes() const { return image_bytes_; }
  uint64_t pages_written() const;  // pages copied on write so far

  const DramController& engine() const { return engine_; }
  const DramStats& stats() const { return engine_.stats(); }
  // The active cycles up to `now` (DramController::settle_active): at a span's end, and before a
  // reset of the statistics.
  void settle_active(Tick now) { engine_.settle_active(now); }
  // The engine's statistics, and <prefix>.held_back with a bounded input queue.
  void register_stats(StatsRegistry& registry, const std::string& prefix) const;
  // Every command the engine issues from now on into a CSV (model/memory/dram_command_trace.h;
  // rtsim/trace if it cannot be written): started again with the statistics (restart), named at
  // close, after which the engine records nothing more.
  void open_command_trace(const TraceRequest& request);
  void restart_command_trace() {
    if (commands_) commands_->restart();
  }
  void close_command_trace();

 private:
  struct Requester {
    uint64_t line;
    tlm::tlm_generic_payload* payload;
  };
  struct Delivery {
    Tick when;
    uint64_t id;  // ids grow with enqueue order: ties deliver in request order
    bool operator>(const Delivery& o) const { return when != o.when ? when > o.when : id > o.id; }
  };

  void host_b_transport(tlm::tlm_generic_payload& p, sc_core::sc_time& delay);
  unsigned int host_transport_dbg(tlm::tlm_generic_payload& p);
  tlm::tlm_sync_enum nb_transport_fw(tlm::tlm_generic_payload& p, tlm::tlm_phase& phase,
                                     sc_core::sc_time& delay);
  // A request's response status if it is not one request_bytes line inside the store.
  tlm::tlm_response_status check(const tlm::tlm_generic_payload& p) const;
  void accept(tlm::tlm_generic_payload& p, Tick arrival);  // into the engine
  void respond(tlm::tlm_generic_payload& p);               // BEGIN_RESP now
  void activate() override;                                // on the calendar
  void wake_for(Tick t);
  bool in_store(uint64_t line_addr) const {
    return line_addr <= store_bytes_ && store_bytes_ - line_addr >= engine_.config().request_bytes;
  }
  uint8_t* writable_line(uint64_t line_addr);  // copies its page on first write

  Calendar& calendar_;
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
  const tlm::tlm_generic_payload* awaiting_end_resp_ = nullptr;  // answered TLM_ACCEPTED
  tlm::tlm_generic_payload* held_back_ = nullptr;  // its channel full: END_REQ not sent yet
  Tick held_back_arrival_ = 0;
  DramTargetStats target_stats_;
  std::unique_ptr<DramCommandTrace> commands_;  // --dram-commands (null: none)
};

}  // namespace rtsim::model
