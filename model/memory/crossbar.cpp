#include "model/memory/crossbar.h"

#include "model/sim/report.h"

#include <algorithm>
#include <stdexcept>

namespace rtsim::model {

void LinkConfig::validate() const {
  RangeCheck check("LinkConfig");
  describe(check, *this);
}

Crossbar::Crossbar(const char* name, const LinkConfig& config, const Clock& clock, uint32_t sources,
                   uint32_t destinations)
    : sc_core::sc_object(name),
      cfg_(config),
      clock_(clock),
      latency_ticks_(clock.cycles(config.latency)) {
  cfg_.validate();
  const uint32_t ports = cfg_.ideal() ? 0 : 1;
  src_out_.assign(sources, PortSchedule(clock_.period(), ports));
  src_in_.assign(sources, PortSchedule(clock_.period(), ports));
  dst_in_.assign(destinations, PortSchedule(clock_.period(), ports));
  dst_out_.assign(destinations, PortSchedule(clock_.period(), ports));
}

Tick Crossbar::transfer(PortSchedule& out, PortSchedule& in, uint32_t payload, Tick t,
                        CrossbarStats& s) {
  ++s.packets;
  if (cfg_.ideal()) return t + latency_ticks_;
  const uint32_t flits = std::max<uint32_t>(
      1, (payload + cfg_.header_bytes + cfg_.bytes_per_cycle - 1) / cfg_.bytes_per_cycle);
  s.flits += flits;
  // In cycles of the crossbar's clock: every time below is one of its edges.
  const uint64_t first = clock_.ceil_cycles(t), hop = cfg_.latency;
  // Both ports free for the whole packet (the common case): each flit leaves and arrives one
  // cycle after the previous, as the loop below would find.
  if (out.run_free(first, flits) && in.run_free(first + hop, flits)) {
    out.take_run(first, flits);
    in.take_run(first + hop, flits);
    return clock_.cycles(first + hop + flits);  // no queueing
  }
  const uint64_t buffer = cfg_.buffer_flits;  // the most cycles a flit may wait there
  uint64_t sent = 0, received = 0;
  for (uint32_t k = 0; k < flits; ++k) {
    uint64_t ready = k == 0 ? first : sent + 1;
    const uint64_t after = k == 0 ? 0 : received + 1;  // flits arrive in order
    if (buffer > 0) {
      // Held at the source while the destination's buffer would be full when it arrived
      const uint64_t taken = in.peek_cycle(std::max(ready + hop, after));
      if (taken > ready + hop + buffer) {
        ++s.held_flits;
        const uint64_t held = taken - hop - buffer;
        out.block(clock_.cycles(ready), clock_.cycles(held));  // nothing else leaves meanwhile
        ready = held;
      }
    }
    sent = out.reserve_cycle(ready);
    received = in.reserve_cycle(std::max(sent + hop, after));
  }
  const uint64_t arrival = received + 1;
  s.queue_cycles += arrival - (first + hop + flits);
  return clock_.cycles(arrival);
}

Tick Crossbar::request(uint32_t src, uint32_t dst, uint32_t payload, Tick t) {
  return transfer(src_out_[src], dst_in_[dst], payload, t, request_);
}

Tick Crossbar::reply(uint32_t dst, uint32_t src, uint32_t payload, Tick t) {
  return transfer(dst_out_[dst], src_in_[src], payload, t, reply_);
}

void Crossbar::register_stats(StatsRegistry& r, const std::string& prefix, const Tick* span) const {
  const uint64_t period = clock_.period();
  auto network = [&](const std::string& dir, const CrossbarStats& s,
                     const std::vector<PortSchedule>* a, const std::vector<PortSchedule>* b) {
    const std::string p = prefix + "." + dir;
    StatsRegistrar v(r, p);
    describe_stats(v, s, dir, cfg_.buffer_flits > 0);
    // The busiest port's share: the ports' schedules', not a counter of the network's.
    r.formula(
        p + ".max_port_utilization",
        [a, b, span, period] {
          const double cycles = double(*span / period);
          uint64_t most = 0;
          for (const auto* ports : {a, b})
            for (const PortSchedule& q : *ports) most = std::max(most, q.stats().requests);
          return cycles > 0 && !a->empty() && !a->front().ideal() ? double(most) / cycles : 0.0;
        },
        "ratio", "the busiest port's flits / cycles");
    // The ports are this crossbar's own (registered read-only, as counters are).
    r.on_reset([a, b] {
      for (const auto* ports : {a, b})
        for (const PortSchedule& q : *ports) const_cast<PortSchedule&>(q).reset_stats();
    });
  };
  network("request", request_, &src_out_, &dst_in_);
  network("reply", reply_, &dst_out_, &src_in_);
}

CrossbarPort::CrossbarPort(Crossbar* crossbar, uint32_t first_source, uint32_t source_ports,
                           LineSource* below, uint32_t line_bytes)
    : xbar_(crossbar),
      first_(first_source),
      source_mask_(source_ports - 1),
      below_(below),
      line_bytes_(line_bytes) {
  if (source_ports == 0 || (source_ports & (source_ports - 1)) != 0)
    report_error(kReportInternal, std::string(xbar_->name()) + ": source ports not a power of two");
  while ((uint64_t(1) << line_shift_) < line_bytes_) ++line_shift_;
}

Tick CrossbarPort::fetch_line(uint64_t line, Tick now, FillListener* listener, uint64_t cookie) {
  if (upstream_ && listener != upstream_)
    report_error(kReportInternal, std::string(xbar_->name()) + ": two requesters on one port");
  upstream_ = listener;
  const uint32_t src = source(line), dst = below_->port_of(line);  // a DRAM channel takes a decode
  const Tick arrived = xbar_->request(src, dst, 0, now);
  const Tick delivered = below_->fetch_line(line, arrived, this, cookie);
  if (delivered == kUnknown) return kUnknown;
  return xbar_->reply(dst, src, line_bytes_, delivered);
}

void CrossbarPort::on_fill(uint64_t line, uint64_t cookie, Tick when) {
  const Tick arrived = xbar_->reply(below_->port_of(line), source(line), line_bytes_, when);
  if (upstream_) upstream_->on_fill(line, cookie, arrived);
}

}  // namespace rtsim::model
