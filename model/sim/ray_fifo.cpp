#include "model/sim/ray_fifo.h"

namespace rtsim::model {

void RayFifo::register_stats(StatsRegistry& r, const std::string& prefix, const Tick* span) const {
  StatsRegistrar v(r, prefix);
  describe_stats(v, stats_, span);
  // The mean's integral is no counter of its own; the owner has integrated up to the reset.
  r.on_reset([this] { const_cast<RayFifo*>(this)->stats_.occupancy_ps = 0; });
}

}  // namespace rtsim::model
