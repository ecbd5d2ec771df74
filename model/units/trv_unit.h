// TRV: kd-tree traversal. Each operation fetches one 8-byte node through the unit's L1 and runs
// one step of the shared traversal state machine (8-cycle pipeline, one operation per cycle).
// A ray whose node misses to memory parks in the ray accumulation buffer until the line arrives.
// A traversal unit (model/units/traversal_unit.h): it pops a ray's stack when IST is done with
// its leaf.
#pragma once

#include "model/sim/stats_description.h"

#include "model/memory/cache.h"
#include "model/units/traversal_unit.h"

namespace rtsim::model {

struct TrvStats {
  uint64_t node_fetches = 0;
  PerRayType node_fetches_by{};  // the same, by ray type
  uint64_t rays_started = 0;
  uint64_t rays_done = 0;
};

// Every TrvStats field, once (model/sim/stats_description.h).
template <class V>
void describe_stats(V& v, const TrvStats& s) {
  v.counter("node_fetches", s.node_fetches, "count", "kd-tree nodes fetched");
  describe_by_ray_type(v, "node_fetches", s.node_fetches_by, "kd-tree nodes fetched");
  v.counter("rays_started", s.rays_started, "count", "rays that began traversal here");
  v.counter("rays_done", s.rays_done, "count", "rays whose traversal ended here");
}

class TrvUnit : public TraversalUnit {
 public:
  // Unit `index` of the TRV units (the owner its rays come back to).
  TrvUnit(sc_core::sc_module_name name, const ModelContext& ctx, const UnitTypeConfig& cfg,
          uint32_t index);

  // RayOwner.
  bool leaf_done(uint32_t ray, Tick when) override;

  const TrvStats& stats() const { return stats_; }
  void register_stats(StatsRegistry& r, const std::string& prefix) const override;

 protected:
  void process(uint32_t ray, Tick now) override;

 private:
  uint32_t latency_;
  TrvStats stats_;
};

}  // namespace rtsim::model
