#include "model/sim/vcd_trace.h"

#include "model/sim/report.h"
#include "model/sim/systemc_time.h"

#include <algorithm>
#include <cstdio>
#include <stdexcept>

namespace rtsim::model {

VcdTrace::VcdTrace(const TraceRequest& request, const Clock& clock, std::function<bool()> pending)
    : request_(request), clock_(clock), pending_(std::move(pending)) {
  // SystemC appends ".vcd"; the file gets its own name only when complete.
  temp_base_ = request_.file + ".part";
  file_ = sc_core::sc_create_vcd_trace_file(temp_base_.c_str());  // opened at sc_start
  probe_ = std::make_unique<PeriodicProbe>("vcd_probe", clock_.period(),
                                           [this](Tick now) { return sample(now); });
}

VcdTrace::~VcdTrace() {
  if (file_) {
    sc_core::sc_close_vcd_trace_file(file_);
    std::remove((temp_base_ + ".vcd").c_str());
  }
}

void VcdTrace::add_fifo(const RayFifo* fifo) {
  add_counter(std::string(fifo->name()) + ".occupancy", [fifo] { return uint64_t(fifo->size()); });
}

void VcdTrace::add_unit(const Unit* unit) {
  busy_.push_back(
      {std::make_unique<sc_core::sc_signal<bool>>(sc_core::sc_gen_unique_name("busy")), unit});
  sc_core::sc_trace(file_, *busy_.back().signal, std::string(unit->name()) + ".busy");
}

void VcdTrace::add_counter(const std::string& name, std::function<uint64_t()> value) {
  counters_.push_back(
      {std::make_unique<sc_core::sc_signal<uint64_t>>(sc_core::sc_gen_unique_name("count")),
       std::move(value)});
  sc_core::sc_trace(file_, *counters_.back().signal, name);
}

void VcdTrace::end_of_elaboration() {
  // Picoseconds, or the resolution if coarser (samples then land on the next representable time).
  // Not when built: asking fixes the resolution, which the platform may set after.
  file_->set_time_unit(double(std::max<Tick>(1, TimeBase::kernel().resolution_ps())),
                       sc_core::SC_PS);
}

void VcdTrace::start() {
  probe_->start_at(clock_.cycles(request_.start_cycle) + clock_.period() / 2);
}

bool VcdTrace::sample(Tick now) {
  const Tick edge = now - clock_.period() / 2;
  if (clock_.to_cycles(edge) >= request_.end_cycle || !pending_()) return false;
  for (Counter& c : counters_) c.signal->write(c.value());
  for (Busy& b : busy_) b.signal->write(b.unit->issued_at(edge));
  return true;
}

void VcdTrace::close() {
  sc_core::sc_close_vcd_trace_file(file_);
  file_ = nullptr;
  if (std::rename((temp_base_ + ".vcd").c_str(), request_.file.c_str()) != 0) {
    std::remove((temp_base_ + ".vcd").c_str());
    report_error(kReportTrace, "cannot move the trace to " + request_.file);
  }
}

}  // namespace rtsim::model
