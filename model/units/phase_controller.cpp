#include "model/units/phase_controller.h"

#include <algorithm>

namespace rtsim::model {

PhaseController::PhaseController(sc_core::sc_module_name name, Schedule schedule,
                                 Calendar& calendar)
    : sc_core::sc_module(name),
      retirements("retirements"),
      primaries("primaries"),
      shadows("shadows"),
      schedule_(schedule),
      calendar_(calendar) {
  retirements.bind(*this);
}

void PhaseController::retired(RayType type, Tick when) {
  const Tick now = calendar_.now();
  end_ = std::max(end_, when);
  // A ray slot is free: whoever waits for one.
  if (!primaries->finished()) primaries->slot_freed(now);
  if (schedule_ == Schedule::kOnePhase) shadows->slot_freed(now);
  if (type == RayType::kShadow) {
    ++shadows_retired_;
    shadows->slot_freed(now);
    return;
  }
  ++primaries_retired_;
  primary_end_ = std::max(primary_end_, when);
  if (primaries->finished() && primaries_retired_ == primaries->issued()) {
    primaries_done_ = true;
    if (schedule_ == Schedule::kTwoPhase)
      shadows->scan_all(std::max(now, primary_end_));
    else
      shadows->close(now);
  }
}

}  // namespace rtsim::model
