// TRV: kd-tree traversal. Each operation fetches one 8-byte node through the unit's L1 and runs
// one step of the shared traversal state machine (8-cycle pipeline, one operation per cycle).
// A ray whose node misses to DRAM parks in the ray accumulation buffer until the line arrives.
// Rays keep their slot here while they visit LIST and IST (the T&I engine's scheme): the unit
// owns at most `capacity` rays, and a ray coming back after its leaf never waits for room.
#pragma once

#include "model/cache.h"
#include "model/ray_unit.h"

namespace rtsim::model {

struct TrvStats {
  uint64_t node_fetches = 0;
  uint64_t rays_started = 0;
  uint64_t rays_done = 0;
};

class TrvUnit : public RayUnit {
 public:
  TrvUnit(sc_core::sc_module_name name, const ModelContext& ctx, uint32_t latency, uint32_t capacity,
          Cache* l1, RayFifo* in, RayFifo* to_list, RayFifo* done);
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
  uint16_t index_ = 0;
  Cache* l1_;
  RayFifo* to_list_;
  RayFifo* done_;
  TrvStats stats_;

 public:
  void set_index(uint16_t i) { index_ = i; }
};

}  // namespace rtsim::model
