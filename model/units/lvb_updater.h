// LVB updater (the paper's Fig. 5): whenever a ray's closest hit is updated after an intersection
// test, the ray takes the LVB word of the leaf that holds the new hit. Two registers and a mux in
// hardware; here a counter of updates. The IST units reach it through their `lvb` ports.
#pragma once

#include "model/sim/stats_description.h"
#include "model/units/ray_ports.h"

#include <systemc>

#include <string>

namespace rtsim::model {

struct LvbUpdaterStats {
  uint64_t updates = 0;
};

// Every LvbUpdaterStats field, once (model/sim/stats_description.h).
template <class V>
void describe_stats(V& v, const LvbUpdaterStats& s) {
  v.counter("updates", s.updates, "count", "closest-hit updates that took a leaf's LVB word");
}

class LvbUpdater : public sc_core::sc_object, public LvbUpdate {
 public:
  explicit LvbUpdater(const char* name) : sc_core::sc_object(name) {}
  const char* kind() const override { return "rtsim_lvb_updater"; }
  uint32_t closest_hit(uint32_t leaf_lvb) override {
    ++stats_.updates;
    return leaf_lvb;
  }
  void register_stats(StatsRegistry& reg, const std::string& prefix) const {
    StatsRegistrar v(reg, prefix);
    describe_stats(v, stats_);
  }

 private:
  LvbUpdaterStats stats_;
};

}  // namespace rtsim::model
