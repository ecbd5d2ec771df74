#include "model/units/ist_unit.h"

namespace rtsim::model {

IstUnit::IstUnit(sc_core::sc_module_name name, const ModelContext& ctx, const UnitTypeConfig& cfg)
    : RayUnit(name, ctx, cfg, kIstStage, "ist"),
      back("back"),
      to_shading("to_shading", this),
      lvb("lvb"),
      latency_(cfg.latency) {}

void IstUnit::admitted(uint32_t ray) {
  // A new leaf (LIST sends a ray here once per leaf).
  IstState& s = ray_state(ray).ist;
  s.tests_issued = 0;
  s.leaf_done_at = 0;
}

void IstUnit::process(uint32_t id, Tick now) {
  RayState& r = ray_state(id);
  IstState& s = r.ist;
  if (!r.faulted && r.list.tris[s.tests_issued] >= ctx_.header.triangles.count)
    fault(id, ImageFault::kTriangleIndex);
  if (r.faulted)  // the image is unreadable (here or in LIST): no more tests, the walk is over
    return emit(to_shading, id, std::max(s.leaf_done_at, now + ctx_.clock.period()), now);
  const RayWalk& walk = r.trv.leaf_walk(ctx_.bvh);
  if (s.tests_issued == 0) s.leaf_ray = traversal_leaf_ray(walk, s.result);
  const uint32_t tri = r.list.tris[s.tests_issued];
  const uint64_t addr = ctx_.header.triangles.base + uint64_t(tri) * image::kTriangleBytes;
  uint8_t bytes[image::kTriangleBytes];
  const Tick ready = load(l1(), id, addr, image::kTriangleBytes, bytes, now);
  if (ready == kUnknown) return;
  const image::TriangleRecord t = image::decode_triangle(bytes);
  ++stats_.tests;
  float t_hit;
  if (intersect_triangle(s.leaf_ray, walk.shear, t.v0, t.v1, t.v2, t_hit)) {
    ++stats_.hits;
    const Hit before = s.result.hit;
    traversal_hit(s.result, walk, tri, t_hit);
    const Hit& after = s.result.hit;
    const bool updated =
        after.tri != before.tri || after.t != before.t || after.leaf != before.leaf;
    if (r.info.type != RayType::kShadow && updated) s.lvb = lvb->closest_hit(r.list.leaf_lvb);
  }
  s.leaf_done_at =
      std::max<Tick>(s.leaf_done_at, std::max(ready, now) + ctx_.clock.cycles(latency_));
  if (++s.tests_issued < r.list.tris.size()) {
    keep(id, now + ctx_.clock.period());  // the next test issues as soon as next cycle
    return;
  }
  // The leaf is done when its last test completes: the ray's TRV unit takes it back, or its
  // traversal is over.
  if (back->leaf_done(id, s.leaf_done_at))
    release();
  else
    emit(to_shading, id, s.leaf_done_at, now);
}

void IstUnit::register_stats(StatsRegistry& r, const std::string& prefix) const {
  register_unit_stats(r, prefix);
  StatsRegistrar v(r, prefix);
  describe_stats(v, stats_);
}

}  // namespace rtsim::model
