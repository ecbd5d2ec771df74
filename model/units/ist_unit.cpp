#include "model/units/ist_unit.h"

#include "model/memory/record_fetch.h"

namespace rtsim::model {

IstUnit::IstUnit(sc_core::sc_module_name name, const ModelContext& ctx, const RayUnitConfig& cfg,
                 MemorySystem& memory, uint32_t index, RayOwners* owners, LvbUpdater* lvb)
    : RayUnit(name, ctx, cfg, memory, MemorySystem::kIst, index),
      latency_(cfg.latency),
      owners_(owners),
      lvb_(lvb) {}

void IstUnit::process(uint32_t id, Tick now) {
  RayState& r = (*ctx_.pool)[id];
  if (r.tests_issued == 0) r.leaf_ray = traversal_leaf_ray(r.trav);
  const uint32_t tri = r.tris[r.tests_issued];
  const uint64_t addr = ctx_.header.triangles.base + uint64_t(tri) * image::kTriangleBytes;
  uint8_t bytes[image::kTriangleBytes];
  const Tick ready = load(l1(), id, addr, image::kTriangleBytes, bytes, now);
  if (ready == kUnknown) return;
  const image::TriangleRecord t = image::decode_triangle(bytes);
  ++stats_.tests;
  float t_hit;
  if (intersect_triangle(r.leaf_ray, r.trav.shear, t.v0, t.v1, t.v2, t_hit)) {
    ++stats_.hits;
    const Hit before = r.trav.hit;
    traversal_hit(r.trav, tri, t_hit);
    const Hit& after = r.trav.hit;
    if (r.type != RayType::kShadow &&
        (after.tri != before.tri || after.t != before.t || after.leaf != before.leaf))
      lvb_->on_closest_hit(r);
  }
  r.leaf_done_at =
      std::max<Tick>(r.leaf_done_at, std::max(ready, now) + ctx_.clock.cycles(latency_));
  if (++r.tests_issued < r.tris.size()) {
    keep(id, now + ctx_.clock.period());  // the next test issues as soon as next cycle
    return;
  }
  // The leaf is done when its last test completes.
  if (traversal_pop(r.trav) == TraversalStep::kFetchNode) {
    release();
    owners_->return_ray(id, r.leaf_done_at);
  } else {
    emit(owners_->shading_input(id), id, r.leaf_done_at, now);
  }
}

void IstUnit::register_stats(StatsRegistry& r, const std::string& prefix) const {
  register_unit_stats(r, prefix);
  r.counter(prefix + ".tests", &stats_.tests, "count", "ray-triangle tests");
  r.counter(prefix + ".hits", &stats_.hits, "count", "tests that hit inside the leaf's window");
}

}  // namespace rtsim::model
