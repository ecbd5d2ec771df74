// Shading: takes every ray whose traversal is over. For a primary or reflection ray it fetches
// the hit triangle and its material through its L1, computes the surface point and keeps it with
// the hit leaf's LVB word for the shadow phase; on a mirror material, while the depth allows, the
// ray goes on as its reflection (same slot). For a shadow ray it records whether the light was
// blocked. A ray that ends retires and its TRV slot frees.
#pragma once

#include "model/memory/cache.h"
#include "model/units/frame_buffer.h"
#include "model/units/hit_record.h"
#include "model/units/ray_owners.h"
#include "model/units/ray_unit.h"

#include <functional>
#include <vector>

namespace rtsim::model {

struct ShadingStats {
  uint64_t primary_rays = 0, primary_hits = 0;
  uint64_t reflection_rays = 0, reflection_hits = 0;
  uint64_t shadow_rays = 0, shadow_occluded = 0;
};

class ShadingUnit : public RayUnit {
 public:
  // Unit `index` of the shading units; rays go back or retire through `owners`; hits land in
  // `frame`.
  ShadingUnit(sc_core::sc_module_name name, const ModelContext& ctx, const RayUnitConfig& cfg,
              MemorySystem& memory, uint32_t index, RayOwners* owners, FrameBuffer* frame);
  // Called after every retirement (the accelerator's phase control listens).
  std::function<void(RayType, Tick)> on_retire;
  // Called when a hit (frame entry) is shaded, with the time its result is ready (one phase).
  std::function<void(uint32_t, Tick)> on_hit;
  // When set, every shaded hit's record is written to the frame buffer in memory through it
  // (a posted write of one line at `records.address(entry)`).
  std::function<void(uint64_t line, const uint8_t* data, Tick when)> write_line;
  HitRecordRegion records;
  const ShadingStats& stats() const { return stats_; }
  void register_stats(StatsRegistry& r, const std::string& prefix) const;

 protected:
  void process(uint32_t ray, Tick now) override;

 private:
  void retire(uint32_t id, RayType type, Tick now);

  uint32_t latency_;
  std::vector<uint8_t> line_;  // the record line being written
  RayOwners* owners_;
  FrameBuffer* frame_;
  ShadingStats stats_;
};

}  // namespace rtsim::model
