#include "model/sim/ray_fifo.h"

namespace rtsim::model {

void RayFifo::register_stats(StatsRegistry& r, const std::string& prefix, const Tick* end) const {
  StatsRegistrar v(r, prefix);
  describe_stats(v, stats_, end);
}

}  // namespace rtsim::model
