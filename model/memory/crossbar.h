// An interconnect with width: a crossbar between `sources` upstream ports (the L1s of a unit type,
// or the L2 banks) and `destinations` downstream ports (the banks of the L2, or the DRAM
// channels), with separate request and reply networks as in GPGPU-Sim.
//
// A packet is its payload plus `header_bytes`, cut into flits of `bytes_per_cycle`; every port
// sends and receives one flit per cycle per direction (model/memory/port_schedule.h, first come,
// first served in the calendar's order). Flit k leaves its source port at the first free cycle at
// or after the previous flit's, and is received at the destination port at the first free cycle at
// or after its departure + `latency`; the packet is there one cycle after its last flit is
// received. So a 64-byte line over a free 32-byte port with no header and no latency takes two
// cycles, and packets that meet at a port queue there. A read request is a header-only packet, a
// reply carries the line.
//
// A destination port's input buffer holds `buffer_flits` flits (GPGPU-Sim's 8-flit buffers):
// a flit that would wait more than buffer_flits cycles there (the flits ahead of it, one served
// per cycle) is held at its source instead, leaving it as late as that allows (credit-based flow
// control). Its arrival does not change, but the source's port is blocked until it leaves: the
// packets behind it at the source wait, whatever their destination (head-of-line blocking).
// 0: unbounded.
//
// `bytes_per_cycle == 0` is the ideal wire: no width, no queueing; only `latency` is added.
//
// CrossbarPort puts a crossbar in front of a LineSource (a cache or the DRAM): the upstream cache
// sees it as the level below.
#pragma once

#include "model/memory/line_source.h"
#include "model/memory/port_schedule.h"
#include "model/sim/config_description.h"
#include "model/sim/stats_description.h"
#include "model/sim/stats_registry.h"
#include "model/sim/time.h"

#include <systemc>

#include <cstdint>
#include <string>
#include <vector>

namespace rtsim::model {

struct LinkConfig {
  uint32_t latency = 0;          // cycles from a flit's departure to its arrival
  uint32_t bytes_per_cycle = 0;  // flit size; 0: an ideal wire of unlimited width
  uint32_t header_bytes = 0;     // added to every packet
  uint32_t buffer_flits = 0;     // a destination port's input buffer; 0: unbounded

  // Throws std::invalid_argument naming the field.
  void validate() const;
  bool ideal() const { return bytes_per_cycle == 0; }
};

// Every LinkConfig field, once (model/sim/config_description.h).
template <class V, class L>
DescribeOf<L, LinkConfig> describe(V& v, L& l) {
  v.number("latency", l.latency, 0, 10000, "cycles", "from a flit's departure to its arrival");
  v.number("bytes_per_cycle", l.bytes_per_cycle, 0, 4096, "bytes",
           "flit size; one flit per cycle per port and direction; 0: an ideal wire");
  v.number("header_bytes", l.header_bytes, 0, 4096, "bytes", "added to every packet");
  v.number("buffer_flits", l.buffer_flits, 0, 65536, "flits",
           "a destination port's input buffer: a flit waits at its source while it would be "
           "full; 0: unbounded (ideal)");
}

struct CrossbarStats {
  uint64_t packets = 0;
  uint64_t flits = 0;
  uint64_t queue_cycles = 0;  // sum over packets of (arrival - arrival on an idle crossbar)
  uint64_t held_flits = 0;
};

// Every CrossbarStats field of one network (`dir`: request or reply), once
// (model/sim/stats_description.h); `buffered`: the destination buffers are bounded.
template <class V>
void describe_stats(V& v, const CrossbarStats& s, const std::string& dir, bool buffered) {
  v.counter("packets", s.packets, "count", dir + " packets");
  v.counter("flits", s.flits, "count", dir + " flits");
  v.counter("queue_cycles", s.queue_cycles, "cycles",
            dir + " cycles packets waited for a port, summed");
  if (buffered)
    v.counter("held_flits", s.held_flits, "count",
              dir + " flits held at their source: the destination's buffer was full");
  v.formula(
      "avg_queue_cycles",
      [&s] { return s.packets ? double(s.queue_cycles) / double(s.packets) : 0.0; }, "cycles",
      "queue_cycles / packets");
}

class Crossbar : public sc_core::sc_object {
 public:
  Crossbar(const char* name, const LinkConfig& config, const Clock& clock, uint32_t sources,
           uint32_t destinations);
  const char* kind() const override { return "rtsim_crossbar"; }

  // A request packet with `payload` bytes from source `src` to destination `dst`, ready to leave
  // at `t`: the time it has arrived.
  Tick request(uint32_t src, uint32_t dst, uint32_t payload, Tick t);
  // A reply packet from destination `dst` back to source `src`.
  Tick reply(uint32_t dst, uint32_t src, uint32_t payload, Tick t);

  const LinkConfig& config() const { return cfg_; }
  uint32_t sources() const { return uint32_t(src_out_.size()); }
  uint32_t destinations() const { return uint32_t(dst_in_.size()); }
  // <prefix>.{request,reply}.{packets,flits,queue_cycles,avg_queue_cycles}, and the busiest
  // port's share of cycles with a flit, .{request,reply}.max_port_utilization, over a window *span
  // long.
  void register_stats(StatsRegistry& r, const std::string& prefix, const Tick* span) const;

 private:
  Tick transfer(PortSchedule& out, PortSchedule& in, uint32_t payload, Tick t, CrossbarStats& s);

  LinkConfig cfg_;
  Clock clock_;
  Tick latency_ticks_;
  std::vector<PortSchedule> src_out_, src_in_, dst_in_, dst_out_;
  CrossbarStats request_, reply_;
};

// One upstream requester's way to a LineSource through a crossbar. The requester uses
// `source_ports` source ports from `first_source` on (a power of two): an L1 one, an L2 one per
// bank, chosen by the line's bank as the L2 banks its lines (model/memory/cache.h: line number
// mod banks, lines of `line_bytes`). The destination port is the level below's port_of(line).
class CrossbarPort : public LineSource, public FillListener {
 public:
  CrossbarPort(Crossbar* crossbar, uint32_t first_source, uint32_t source_ports, LineSource* below,
               uint32_t line_bytes);

  Tick fetch_line(uint64_t line_addr, Tick now, FillListener* listener, uint64_t cookie) override;
  uint32_t line_bytes() const override { return line_bytes_; }
  const uint8_t* line_data(uint64_t line_addr) const override {
    return below_->line_data(line_addr);
  }
  uint32_t port_of(uint64_t line_addr) const override { return below_->port_of(line_addr); }
  uint32_t port_count() const override { return below_->port_count(); }
  // The level below answered a request whose time it did not know: the reply crosses back.
  void on_fill(uint64_t line_addr, uint64_t cookie, Tick when) override;

 private:
  uint32_t source(uint64_t line) const {
    return first_ + uint32_t((line >> line_shift_) & source_mask_);
  }

  Crossbar* xbar_;
  uint32_t first_;
  uint64_t source_mask_;
  uint32_t line_shift_ = 0;
  LineSource* below_;
  uint32_t line_bytes_;
  FillListener* upstream_ = nullptr;  // the requester (one listener per port)
};

}  // namespace rtsim::model
