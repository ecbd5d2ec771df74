// The DRAM as a SystemC module: a thin wrapper that drives the DramController engine in
// simulated time and serves the memory image's bytes.
//
// fetch_line enqueues a read and returns kUnknown (DRAM times are decided by the scheduler). An
// activation on the scheduler's calendar advances the engine to the current time, and tells each
// requester through FillListener::on_fill at the first accelerator-clock edge at or after the
// data are ready (the DRAM runs on its own command clock; the accelerator samples on its own).
// Deliveries later than now wait in a small time-ordered queue. The module re-arms for the
// earliest of the engine's next event and the next delivery, so it costs no activation while idle. Needs sc_set_time_resolution(1, SC_PS).
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
#include <queue>
#include <string>
#include <unordered_map>
#include <vector>

namespace rtsim::model {

class Dram : public sc_core::sc_module, public LineSource, public Scheduler::Client {
 public:
  // `memory` is the loaded memory image (may be null for a timing-only model; line_data then
  // throws). It must outlive the module.
  Dram(sc_core::sc_module_name name, const DramConfig& config, const std::vector<uint8_t>* memory,
       const Clock& accel_clock);

  // Returns kUnknown; `listener->on_fill(line_addr, cookie, t)` follows at delivery time t
  // (`listener` may be null). `now` earlier than the simulation time is taken as now; a later
  // `now` (a requester's own latency already added) is honoured. `line_addr` must be
  // request_bytes-aligned (std::logic_error) and inside the image (std::out_of_range).
  Tick fetch_line(uint64_t line_addr, Tick now, FillListener* listener, uint64_t cookie) override;
  // Pointer into the memory image; std::out_of_range if the line is not wholly inside it.
  const uint8_t* line_data(uint64_t line_addr) const override;
  // The channel a line maps to (a crossbar's destination port).
  uint32_t port_of(uint64_t line_addr) const override { return engine_.mapping().decode(line_addr).channel; }
  uint32_t port_count() const override { return engine_.config().channels; }

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

  DramController engine_;
  const std::vector<uint8_t>* memory_;
  Clock accel_clock_;
  std::unordered_map<uint64_t, Requester> requesters_;  // by request id
  std::priority_queue<Delivery, std::vector<Delivery>, std::greater<Delivery>> deliveries_;
  std::vector<DramController::Completion> done_;  // scratch
  uint64_t next_id_ = 0;
};

}  // namespace rtsim::model
