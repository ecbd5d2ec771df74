// A one-line progress report for long runs on a terminal: phase, rays retired, simulated cycles,
// host time and the phase's ETA, redrawn at most twice a second. Silent when stderr is not a
// terminal (logs, sweeps, CI) or when disabled.
#pragma once

#include "model/accelerator.h"

#include <chrono>
#include <string>

namespace rtsim {

class ProgressLine {
 public:
  ProgressLine(std::string label, bool enabled);
  void update(const model::Progress& p);
  void finish();  // erases the line

 private:
  std::string label_;
  bool enabled_;
  bool drawn_ = false;
  int phase_ = 0;
  std::chrono::steady_clock::time_point start_, phase_start_, last_draw_;
};

}  // namespace rtsim
