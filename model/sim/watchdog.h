// Stops a run that makes no progress: every `interval` cycles while work is pending it compares a
// progress count (operations issued, rays retired) with the last one; if nothing moved, it reports
// an error of type rtsim/watchdog (model/sim/report.h) naming the FIFOs and units that still hold
// rays (the default sc_report action throws it out of sc_start; the testbench turns it into its
// message).
#pragma once

#include "model/sim/report.h"
#include "model/sim/unit.h"

#include <functional>
#include <string>

namespace rtsim::model {

class Watchdog : public Unit {
 public:
  Watchdog(sc_core::sc_module_name name, Calendar& calendar, const Clock& clock,
           uint64_t interval_cycles, std::function<uint64_t()> progress,
           std::function<bool()> pending, std::function<std::string()> describe)
      : Unit(name, calendar, clock),
        interval_(interval_cycles),
        progress_(std::move(progress)),
        pending_(std::move(pending)),
        describe_(std::move(describe)) {}
  void start() {
    last_ = ~0ull;  // a new frame's count (the statistics may have started again from 0)
    wake(now_ps() + clock().cycles(interval_));
  }
  bool fired() const { return !report_.empty(); }
  const std::string& report() const { return report_; }

 protected:
  bool cycle(Tick now) override {
    if (!pending_()) return false;
    const uint64_t p = progress_();
    if (p == last_) {
      report_ = "no progress for " + std::to_string(interval_) + " cycles at cycle " +
                std::to_string(clock().to_cycles(now)) + "; " + describe_();
      report_error(kReportWatchdog, report_);
    }
    last_ = p;
    wake(now + clock().cycles(interval_));
    return false;
  }
  Tick next_ready(Tick) const override { return kUnknown; }  // it re-arms itself in cycle()
  bool holds_work() const override { return false; }

 private:
  uint64_t interval_;
  std::function<uint64_t()> progress_;
  std::function<bool()> pending_;
  std::function<std::string()> describe_;
  uint64_t last_ = ~0ull;
  std::string report_;
};

}  // namespace rtsim::model
