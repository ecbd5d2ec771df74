// Phase control: when the shadow rays go. In two phases (the paper's Table 6) the shadow culling
// unit starts its scan of the frame when the last primary ray retires; in one phase it takes each
// hit as it is shaded and learns at that moment that no more will come. It also wakes whoever
// waits for a ray slot when one frees, and keeps the times the frame's phases end.
//
// Export: `retirements` (the router tells it of every retirement). Ports: `primaries` (the ray
// generator), `shadows` (the shadow culling unit).
#pragma once

#include "model/sim/calendar.h"
#include "model/sim/time.h"
#include "model/units/ray_ports.h"

#include <systemc>

#include <cstdint>

namespace rtsim::model {

// When shadow rays go: after every primary ray (two phases, the paper's Table 6), or as soon as
// their hit is shaded (one phase: primary and shadow rays overlap).
enum class Schedule { kTwoPhase, kOnePhase };

class PhaseController : public sc_core::sc_module, public RetireListener {
 public:
  sc_core::sc_export<RetireListener> retirements;
  sc_core::sc_port<PrimaryRays> primaries;
  sc_core::sc_port<ShadowRays> shadows;

  PhaseController(sc_core::sc_module_name name, Schedule schedule, Calendar& calendar);
  const char* kind() const override { return "rtsim_phase_controller"; }

  // A new frame, starting at `begin`.
  void begin_frame(Tick begin) {
    primaries_done_ = false;
    primaries_retired_ = shadows_retired_ = 0;
    primary_end_ = end_ = begin;
  }

  // RetireListener: a ray retired at `when`; a primary or reflection ray ends its pixel's chain.
  void retired(RayType type, Tick when) override;

  bool primaries_done() const { return primaries_done_; }
  // Every ray has retired and the culling unit has decided every (hit, light) pair.
  bool finished() const {
    return primaries_done_ && shadows->finished() && shadows_retired_ == shadows->generated();
  }
  uint64_t primaries_retired() const { return primaries_retired_; }
  uint64_t shadows_retired() const { return shadows_retired_; }
  Tick primary_end() const { return primary_end_; }  // the last primary retirement
  Tick end() const { return end_; }                  // the last retirement

 private:
  Schedule schedule_;
  Calendar& calendar_;
  bool primaries_done_ = false;
  uint64_t primaries_retired_ = 0, shadows_retired_ = 0;
  Tick primary_end_ = 0, end_ = 0;
};

}  // namespace rtsim::model
