// A sampled frame's windows of detail (issue 38, docs/sampling.md). A phase's work (primary rays
// in issue order, the culling unit's record slots in the same order) runs in detail only inside
// its windows; between two windows the unit waits until the machine holds no ray, then jumps to
// the next window's first ray. Each window is timed by batches of kBatchRays, as a full frame is
// (AcceleratorResult::primary_batch_cycles): the measured windows are the sample.
#pragma once

#include "model/sim/time.h"
#include "model/units/ray_ports.h"

#include <cstdint>
#include <string>
#include <vector>

namespace rtsim::model {

struct DetailWindow {
  uint64_t begin = 0, end = 0;  // [begin, end) of the phase's work
};

// What is wrong with `windows` over `total` units of work, or "" when they can run: in order,
// each at least a batch long, starting on a batch and ending on one (or at `total`), and at least
// a batch apart (the ray generator issues ray `end` to time the window's last batch).
std::string check_windows(const std::vector<DetailWindow>& windows, uint64_t total);

// The windows a full frame runs: one over all `total` units of work.
inline std::vector<DetailWindow> whole_frame(uint64_t total) { return {DetailWindow{0, total}}; }

// A window's batches (its first at window.begin / kBatchRays), each from its start to the next's,
// the last to `last_end` when the window reaches the phase's end, else to the start of the
// batch at window.end (the last of `starts`).
struct WindowBatches {
  uint64_t first_batch = 0;
  std::vector<uint64_t> cycles;
};
WindowBatches window_batches(const Clock& clock, const DetailWindow& window, uint64_t total,
                             const std::vector<Tick>& starts, Tick last_end);

}  // namespace rtsim::model
