#include "model/units/shading_unit.h"

#include "model/memory/record_fetch.h"

namespace rtsim::model {

ShadingUnit::ShadingUnit(sc_core::sc_module_name name, const ModelContext& ctx,
                         const RayUnitConfig& cfg, MemorySystem& memory, uint32_t index,
                         RayOwners* owners, FrameBuffer* frame)
    : RayUnit(name, ctx, cfg, memory, MemorySystem::kShading, index),
      latency_(cfg.latency),
      owners_(owners),
      frame_(frame) {}

void ShadingUnit::process(uint32_t id, Tick now) {
  RayState& r = (*ctx_.pool)[id];
  if (r.type == RayType::kShadow) {
    PixelState& px = frame_->pixels[r.pixel];
    ++stats_.shadow_rays;
    if (r.trav.found) {
      if (ctx_.light_samples[r.light] > 1)
        frame_->set_sample_occluded(r.pixel, r.light, r.sample);
      else
        px.occluded |= uint16_t(1u << r.light);
      ++stats_.shadow_occluded;
    }
    return retire(id, RayType::kShadow, now);
  }
  if (!r.trav.found) {
    ++(r.type == RayType::kPrimary ? stats_.primary_rays : stats_.reflection_rays);
    return retire(id, RayType::kPrimary, now);
  }
  PixelState& px = frame_->at(r.pixel, r.depth);
  // The triangle, then its material; a parked ray resumes at the stage it waited in.
  const image::Header& h = ctx_.header;
  if (r.stage == 0) {
    const uint64_t addr = h.triangles.base + uint64_t(r.trav.hit.tri) * image::kTriangleBytes;
    uint8_t bytes[image::kTriangleBytes];
    const Tick ready = load(l1(), id, addr, image::kTriangleBytes, bytes, now);
    if (ready == kUnknown) return;
    const image::TriangleRecord tri = image::decode_triangle(bytes);
    r.surface = surface_point(r.trav.ray, r.trav.hit.t, tri.v0, tri.v1, tri.v2);
    r.material = tri.material;
    r.stage = 1;
    return keep(id, std::max(ready, now + ctx_.clock.period()));
  }
  const uint64_t addr = h.materials.base + uint64_t(r.material) * image::kMaterialBytes;
  uint8_t bytes[image::kMaterialBytes];
  const Tick ready = load(l1(), id, addr, image::kMaterialBytes, bytes, now);
  if (ready == kUnknown) return;
  const image::MaterialRecord mat = image::decode_material(bytes);
  ++(r.type == RayType::kPrimary ? stats_.primary_rays : stats_.reflection_rays);
  ++(r.type == RayType::kPrimary ? stats_.primary_hits : stats_.reflection_hits);
  px.hit = r.trav.hit;
  px.lvb = r.lvb;
  px.surface = r.surface;
  px.diffuse = mat.diffuse;
  px.reflectance = mat.reflectance;
  const Tick done_at = std::max(ready, now) + ctx_.clock.cycles(latency_);
  const uint32_t entry = frame_->entry(r.pixel, r.depth);
  if (write_line) {
    line_.assign(records.stride, 0);
    encode_hit_record(px, line_.data());
    write_line(records.address(entry), line_.data(), done_at);
  }
  if (on_hit) on_hit(entry, done_at);
  if (mat.reflectance > 0.f && r.depth + 1 < frame_->levels) {
    // A mirror: the ray goes on as its reflection, in the same slot of the same TRV unit.
    const Ray incoming = r.trav.ray;
    r.type = RayType::kReflection;
    ++r.depth;
    r.started = false;
    r.stage = 0;
    r.lvb = r.leaf_lvb = 0;
    r.trav.ray = reflection_ray(r.surface, incoming.d, ctx_.shadow_offset);
    release();
    owners_->return_ray(id, done_at);
    return;
  }
  retire(id, RayType::kPrimary, done_at);
}

void ShadingUnit::retire(uint32_t id, RayType type, Tick when) {
  owners_->retire(id);
  release();
  ctx_.pool->release(id);
  if (on_retire) on_retire(type, when);
}

void ShadingUnit::register_stats(StatsRegistry& r, const std::string& prefix) const {
  register_unit_stats(r, prefix);
  r.counter(prefix + ".primary_rays", &stats_.primary_rays, "count", "primary rays shaded");
  r.counter(prefix + ".primary_hits", &stats_.primary_hits, "count", "primary rays that hit");
  r.counter(prefix + ".reflection_rays", &stats_.reflection_rays, "count",
            "reflection rays shaded");
  r.counter(prefix + ".reflection_hits", &stats_.reflection_hits, "count",
            "reflection rays that hit");
  r.counter(prefix + ".shadow_rays", &stats_.shadow_rays, "count", "shadow rays finished");
  r.counter(prefix + ".shadow_occluded", &stats_.shadow_occluded, "count",
            "shadow rays that were blocked");
}

}  // namespace rtsim::model
