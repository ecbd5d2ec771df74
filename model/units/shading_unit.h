// Shading: takes every ray whose traversal is over. For a primary, reflection or bounce ray with a
// hit it fetches the hit triangle and its material through its L1, computes the surface point and
// keeps it with the hit leaf's LVB word for the shadow phase (the frame entry, and the entry's hit
// record written to the frame buffer in memory). Then, in a Whitted frame, on a mirror material
// while the depth allows, the ray goes on as its reflection (same slot); in a path-traced frame,
// below max_depth, as the path's next ray (a reflection or a diffuse bounce, same slot, the
// random numbers and Russian roulette of kernels/path_sampling.h). For a shadow ray it records
// whether the light was blocked. A ray that ends retires.
//
// Ports: `back` (RayReturn: reflections and retirements), `hits` (one phase: the culling unit
// takes each shaded hit), `records` (the frame buffer's writes; unbound: none are written). A hit
// needs an entry of the posted-write buffer behind `records`: while it is full the unit stalls
// (an in-order pipeline: the rays behind the hit wait too) until memory acknowledges a write.
#pragma once

#include "model/sim/stats_description.h"

#include "model/memory/cache.h"
#include "model/units/frame_buffer.h"
#include "model/units/hit_record.h"
#include "model/units/ray_ports.h"
#include "model/units/ray_unit.h"

#include <vector>

namespace rtsim::model {

struct ShadingStats {
  uint64_t primary_rays = 0, primary_hits = 0;
  uint64_t reflection_rays = 0, reflection_hits = 0;
  uint64_t bounce_rays = 0, bounce_hits = 0;
  uint64_t shadow_rays = 0, shadow_occluded = 0;
};

// A path-traced frame's figures by bounce (0: the primary rays): its rays and the shadow (NEE)
// rays from its hits, with their cycles in flight (made to shaded, summed over the rays).
struct BounceStats {
  uint64_t rays = 0, hits = 0, ray_cycles = 0;
  uint64_t shadow_rays = 0, shadow_occluded = 0, shadow_cycles = 0;
};

// Every ShadingStats field, once (model/sim/stats_description.h).
template <class V>
void describe_stats(V& v, const ShadingStats& s) {
  v.counter("primary_rays", s.primary_rays, "count", "primary rays shaded");
  v.counter("primary_hits", s.primary_hits, "count", "primary rays that hit");
  v.counter("reflection_rays", s.reflection_rays, "count", "reflection rays shaded");
  v.counter("reflection_hits", s.reflection_hits, "count", "reflection rays that hit");
  v.counter("bounce_rays", s.bounce_rays, "count", "diffuse bounce rays shaded (paths)");
  v.counter("bounce_hits", s.bounce_hits, "count", "diffuse bounce rays that hit (paths)");
  v.counter("shadow_rays", s.shadow_rays, "count", "shadow rays finished");
  v.counter("shadow_occluded", s.shadow_occluded, "count", "shadow rays that were blocked");
}

// Every BounceStats field, once.
template <class V>
void describe_stats(V& v, const BounceStats& s) {
  v.counter("rays", s.rays, "count", "the bounce's rays shaded");
  v.counter("hits", s.hits, "count", "the bounce's rays that hit");
  v.counter("ray_cycles", s.ray_cycles, "cycles", "the bounce's rays' cycles in flight, summed");
  v.counter("shadow_rays", s.shadow_rays, "count", "shadow rays from the bounce's hits finished");
  v.counter("shadow_occluded", s.shadow_occluded, "count", "... that were blocked");
  v.counter("shadow_cycles", s.shadow_cycles, "cycles", "their cycles in flight, summed");
}

class ShadingUnit : public RayUnit {
 public:
  sc_core::sc_port<RayReturn> back;
  sc_core::sc_port<ShadedHits, 1, sc_core::SC_ZERO_OR_MORE_BOUND> hits;
  sc_core::sc_port<LineWriter, 1, sc_core::SC_ZERO_OR_MORE_BOUND> records;

  // Hits land in `frame`, and their records at `region` (both the accelerator's, updated in place
  // for each frame).
  ShadingUnit(sc_core::sc_module_name name, const ModelContext& ctx, const UnitTypeConfig& cfg,
              FrameBuffer* frame, const HitRecordRegion& region);
  const ShadingStats& stats() const { return stats_; }
  // Path-traced frames: by bounce, 0 to max_depth (else empty).
  const std::vector<BounceStats>& bounces() const { return bounces_; }
  void register_stats(StatsRegistry& r, const std::string& prefix) const override;

 protected:
  void process(uint32_t ray, Tick now) override;
  void admitted(uint32_t ray) override {
    ray_state(ray).shading.next = ShadingState::Next::kTriangle;
  }
  bool gate_open() const override { return !records->full(); }
  void end_of_elaboration() override;

 private:
  void shadow_done(uint32_t id, Tick now);
  void shade(uint32_t id, const image::MaterialRecord& mat, Tick done_at);
  // A path's next ray from the hit in slot `id`, unless the path ends there: true if it goes on.
  bool go_on_path(uint32_t id, const image::MaterialRecord& mat, Tick done_at);
  void count_ray(const RayInfo& info, bool hit, Tick when);
  void retire(uint32_t id, RayType type, Tick when);

  uint32_t latency_;
  FrameBuffer* frame_;
  const HitRecordRegion& region_;
  std::vector<uint8_t> line_;  // the record line being written
  ShadingStats stats_;
  std::vector<BounceStats> bounces_;  // sized once: the registry holds their addresses
};

}  // namespace rtsim::model
