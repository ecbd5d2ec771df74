#include "model/units/detail_window.h"

#include <algorithm>

namespace rtsim::model {

std::string check_windows(const std::vector<DetailWindow>& windows, uint64_t total) {
  uint64_t free_from = 0;  // the first ray the next window may begin at
  for (size_t i = 0; i < windows.size(); ++i) {
    const DetailWindow& w = windows[i];
    const std::string which = "window " + std::to_string(i) + " [" + std::to_string(w.begin) +
                              ", " + std::to_string(w.end) + ")";
    if (w.begin < free_from || w.end <= w.begin || w.end > total)
      return which + ": windows must be non-empty, in order, at least a batch apart and within " +
             std::to_string(total);
    if (w.begin % kBatchRays != 0 || (w.end % kBatchRays != 0 && w.end != total))
      return which + ": windows begin and end on batches of " + std::to_string(kBatchRays);
    free_from = w.end + kBatchRays;
  }
  return "";
}

WindowBatches window_batches(const Clock& clock, const DetailWindow& window, uint64_t total,
                             const std::vector<Tick>& starts, Tick last_end) {
  WindowBatches out;
  out.first_batch = window.begin / kBatchRays;
  const size_t batches = (window.end - window.begin + kBatchRays - 1) / kBatchRays;
  out.cycles.reserve(batches);
  for (size_t b = 0; b < batches && b < starts.size(); ++b) {
    // The scan may reach its last batch after the last retirement (records with no ray to emit):
    // that batch then takes no time.
    const Tick next = std::max(b + 1 < starts.size() ? starts[b + 1] : last_end, starts[b]);
    if (b + 1 == starts.size() && window.end < total) break;  // never reached the next batch
    out.cycles.push_back(clock.to_cycles(clock.edge_at_or_after(next)) -
                         clock.to_cycles(starts[b]));
  }
  return out;
}

}  // namespace rtsim::model
