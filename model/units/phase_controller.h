// Phase control: when the shadow rays go. In two phases (the paper's Table 6) the shadow culling
// unit starts its scan of the frame when the last primary ray retires; in one phase it takes each
// hit as it is shaded and learns at that moment that no more will come. It also wakes whoever
// waits for a ray slot when one frees, and keeps the times the frame's phases end.
#pragma once

#include "model/sim/calendar.h"
#include "model/sim/time.h"
#include "model/units/ray_generator.h"
#include "model/units/ray_state.h"
#include "model/units/shadow_culling_unit.h"

#include <cstdint>

namespace rtsim::model {

// When shadow rays go: after every primary ray (two phases, the paper's Table 6), or as soon as
// their hit is shaded (one phase: primary and shadow rays overlap).
enum class Schedule { kTwoPhase, kOnePhase };

class PhaseController {
 public:
  PhaseController(Schedule schedule, Calendar& calendar, RayGenerator& generator,
                  ShadowCullingUnit& culling)
      : schedule_(schedule), calendar_(calendar), generator_(generator), culling_(culling) {}

  // A ray retired at `when` (a shading unit's on_retire).
  void on_retire(RayType type, Tick when);
  // A hit (frame entry) is shaded by `ready` (one phase: a shading unit's on_hit).
  void on_hit(uint32_t entry, Tick ready) { culling_.add(entry, ready); }

  bool primaries_done() const { return primaries_done_; }
  // Every ray has retired and the culling unit has decided every (hit, light) pair.
  bool finished() const {
    return primaries_done_ && culling_.finished() && shadows_retired_ == culling_.generated();
  }
  uint64_t primaries_retired() const { return primaries_retired_; }
  uint64_t shadows_retired() const { return shadows_retired_; }
  Tick primary_end() const { return primary_end_; }  // the last primary retirement
  Tick end() const { return end_; }                  // the last retirement

 private:
  Schedule schedule_;
  Calendar& calendar_;
  RayGenerator& generator_;
  ShadowCullingUnit& culling_;
  bool primaries_done_ = false;
  uint64_t primaries_retired_ = 0, shadows_retired_ = 0;
  Tick primary_end_ = 0, end_ = 0;
};

}  // namespace rtsim::model
