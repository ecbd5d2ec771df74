// TRV: kd-tree traversal. Each operation fetches one 8-byte node through the unit's L1 and runs
// one step of the shared traversal state machine (8-cycle pipeline, one operation per cycle).
// A ray whose node misses to DRAM parks in the ray accumulation buffer until the line arrives.
// Rays keep their slot here while they visit LIST and IST (the T&I engine's scheme): the unit
// owns at most `capacity` rays, and a ray coming back after its leaf never waits for room.
#pragma once

#include "model/memory/cache.h"
#include "model/units/ray_owners.h"
#include "model/units/ray_unit.h"

namespace rtsim::model {

struct TrvStats {
  uint64_t node_fetches = 0;
  uint64_t rays_started = 0;
  uint64_t rays_done = 0;
};

class TrvUnit : public RayUnit {
 public:
  // Unit `index` of the TRV units; its rays go to `to_list`, and to their shading unit via
  // `owners`.
  TrvUnit(sc_core::sc_module_name name, const ModelContext& ctx, const RayUnitConfig& cfg,
          MemorySystem& memory, uint32_t index, RayFifo* to_list, RayOwners* owners);
  // IST hands a ray back after its leaf: it continues at `when`.
  void return_ray(uint32_t ray, Tick when) { take_back(ray, when); }
  // The ray retired (shading took it): its slot frees.
  void retire(uint32_t) {
    --owned_;
    wake(now_ps());
  }
  const TrvStats& stats() const { return stats_; }
  void register_stats(StatsRegistry& r, const std::string& prefix) const;

 protected:
  void process(uint32_t ray, Tick now) override;
  bool can_admit() const override { return owned_ < capacity_; }
  void admitted(uint32_t ray) override;
  bool holds_work() const override { return RayUnit::holds_work() || owned_ > 0; }

 private:
  uint32_t latency_, capacity_;
  uint32_t owned_ = 0;
  uint16_t index_;
  RayFifo* to_list_;
  RayOwners* owners_;
  TrvStats stats_;
};

}  // namespace rtsim::model
