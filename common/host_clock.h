// Host time of the testbench's steps (report.json's host.seconds), on the monotonic clock.
#pragma once

#include <chrono>

namespace rtsim {

// Seconds from `t0` to now.
inline double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace rtsim
