#include "model/sim/ray_fifo.h"

namespace rtsim::model {

void RayFifo::register_stats(StatsRegistry& r, const std::string& prefix, const Tick* end) const {
  r.counter(prefix + ".pushes", &stats_.pushes, "count", "rays pushed");
  r.counter(prefix + ".max_occupancy", &stats_.max_occupancy, "rays", "largest occupancy");
  r.counter(prefix + ".full_events", &stats_.full_events, "count", "pushes refused while full");
  r.formula(
      prefix + ".mean_occupancy",
      [this, end] { return *end ? double(stats_.occupancy_ps) / double(*end) : 0.0; }, "rays",
      "time-weighted mean occupancy");
}

}  // namespace rtsim::model
