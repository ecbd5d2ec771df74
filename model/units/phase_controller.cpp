#include "model/units/phase_controller.h"

#include <algorithm>

namespace rtsim::model {

void PhaseController::on_retire(RayType type, Tick when) {
  const Tick now = calendar_.now();
  end_ = std::max(end_, when);
  // A ray slot is free: whoever waits for one.
  if (!generator_.finished()) generator_.wake(now);
  if (schedule_ == Schedule::kOnePhase) culling_.wake(now);
  if (type == RayType::kPrimary) {
    ++primaries_retired_;
    primary_end_ = std::max(primary_end_, when);
    if (generator_.finished() && primaries_retired_ == generator_.issued()) {
      primaries_done_ = true;
      if (schedule_ == Schedule::kTwoPhase)
        culling_.scan_all(std::max(now, primary_end_));
      else
        culling_.close(now);
    }
  } else {
    ++shadows_retired_;
    culling_.wake(now);
  }
}

}  // namespace rtsim::model
