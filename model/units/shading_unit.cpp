#include "model/units/shading_unit.h"

#include "kernels/path_sampling.h"

namespace rtsim::model {

ShadingUnit::ShadingUnit(sc_core::sc_module_name name, const ModelContext& ctx,
                         const UnitTypeConfig& cfg, FrameBuffer* frame,
                         const HitRecordRegion& region)
    : RayUnit(name, ctx, cfg, kShadingStage, "shading"),
      back("back"),
      hits("hits"),
      records("records"),
      latency_(cfg.latency),
      frame_(frame),
      region_(region) {
  if (ctx.paths()) bounces_.resize(size_t(ctx.path.max_depth) + 1);
}

void ShadingUnit::end_of_elaboration() {
  RayUnit::end_of_elaboration();
  if (records.size() > 0) records->on_room([this](Tick when) { wake(when); });
}

void ShadingUnit::process(uint32_t id, Tick now) {
  RayState& r = ray_state(id);
  if (r.info.type == RayType::kShadow) return shadow_done(id, now);
  const TraversalResult& result = r.ist.result;
  if (!result.found || r.faulted) {  // a ray that met an unreadable image ends as a miss
    count_ray(r.info, false, now);
    return retire(id, r.info.type, now);
  }
  // The triangle, then its material; a parked ray resumes at the stage it waited in.
  ShadingState& s = r.shading;
  const image::Header& h = ctx_.header;
  if (s.next == ShadingState::Next::kTriangle) {
    const uint64_t addr = h.triangles.base + uint64_t(result.hit.tri) * image::kTriangleBytes;
    uint8_t bytes[image::kTriangleBytes];
    const Tick ready = load(l1(), id, addr, image::kTriangleBytes, bytes, now);
    if (ready == kUnknown) return;
    const image::TriangleRecord tri = image::decode_triangle(bytes);
    s.surface = surface_point(r.info.ray, result.hit.t, tri.v0, tri.v1, tri.v2);
    s.material = tri.material;
    s.next = ShadingState::Next::kMaterial;
    return keep(id, std::max(ready, now + ctx_.clock.period()));
  }
  if (records.size() > 0 && records->full()) {
    return hold_back(id);  // its record needs an entry: the unit stalls
  }
  if (s.material >= h.materials.count) {
    fault(id, ImageFault::kMaterialIndex);
    return process(id, now);  // a miss
  }
  const uint64_t addr = h.materials.base + uint64_t(s.material) * image::kMaterialBytes;
  uint8_t bytes[image::kMaterialBytes];
  const Tick ready = load(l1(), id, addr, image::kMaterialBytes, bytes, now);
  if (ready == kUnknown) return;
  shade(id, image::decode_material(bytes), std::max(ready, now) + ctx_.clock.cycles(latency_));
}

void ShadingUnit::shadow_done(uint32_t id, Tick now) {
  const RayInfo& info = ray_state(id).info;
  ++stats_.shadow_rays;
  const bool blocked = ray_state(id).ist.result.found && !ray_state(id).faulted;
  if (!bounces_.empty()) {
    BounceStats& b = bounces_[info.depth];
    ++b.shadow_rays;
    b.shadow_occluded += blocked;
    b.shadow_cycles += clock().to_cycles(now) - clock().to_cycles(info.born);
  }
  if (blocked) {
    if (ctx_.light_samples[info.light] > 1)
      frame_->set_sample_occluded(info.entry, info.light, info.sample);
    else
      frame_->pixels[info.entry].occluded |= uint16_t(1u << info.light);
    ++stats_.shadow_occluded;
  }
  retire(id, RayType::kShadow, now);
}

// The hit's frame entry (and its record in memory); then the reflection or the retirement.
void ShadingUnit::shade(uint32_t id, const image::MaterialRecord& mat, Tick done_at) {
  RayState& r = ray_state(id);
  const RayInfo info = r.info;
  count_ray(info, true, done_at);
  PixelState& px = frame_->pixels[info.entry];
  px.hit = r.ist.result.hit;
  px.lvb = r.ist.lvb;
  px.surface = r.shading.surface;
  px.diffuse = mat.diffuse;
  px.reflectance = mat.reflectance;
  const uint32_t entry = info.entry;
  if (records.size() > 0) {
    line_.assign(region_.stride, 0);
    encode_hit_record(px, line_.data());
    records->write_line(region_.address(entry), line_.data(), done_at);
  }
  if (hits.size() > 0) hits->hit_shaded(entry, done_at);
  if (ctx_.paths()) {
    if (!go_on_path(id, mat, done_at)) retire(id, info.type, done_at);
    return;
  }
  if (mat.reflectance > 0.f && info.depth + 1 < frame_->levels) {
    // A mirror: a new ray, the reflection, in the same slot of the same TRV unit.
    RayInfo reflection = info;
    reflection.type = RayType::kReflection;
    reflection.depth = uint8_t(info.depth + 1);
    reflection.entry = info.entry + uint32_t(frame_->pixel_count());  // its pixel, a bounce on
    reflection.ray = reflection_ray(r.shading.surface, info.ray.d, ctx_.shadow_offset);
    reflection.born = done_at;
    ctx_.pool->renew(id, reflection);
    release();
    back->reflect(id, done_at);
    return;
  }
  retire(id, info.type, done_at);
}

bool ShadingUnit::go_on_path(uint32_t id, const image::MaterialRecord& mat, Tick done_at) {
  const RayState& r = ray_state(id);
  const RayInfo& info = r.info;
  const uint32_t bounce = info.depth;
  if (int(bounce) == ctx_.path.max_depth) return false;
  const uint32_t pixel = frame_->pixel_of(info.entry), path = frame_->path_of(info.entry);
  RayInfo next = info;
  bool mirror = false;
  next.ray = path_bounce(r.shading.surface, info.ray.d, mat.diffuse, mat.reflectance, pixel, path,
                         bounce, ctx_.shadow_offset, next.throughput, &mirror);
  if (!path_survives(next.throughput, pixel, path, bounce, ctx_.path)) return false;
  next.type = mirror ? RayType::kReflection : RayType::kBounce;
  next.depth = uint8_t(bounce + 1);
  next.entry = info.entry + uint32_t(frame_->pixel_count());  // its pixel, a bounce on
  next.born = done_at;
  ctx_.pool->renew(id, next);
  release();
  back->reflect(id, done_at);
  return true;
}

void ShadingUnit::count_ray(const RayInfo& info, bool hit, Tick when) {
  switch (info.type) {
    case RayType::kPrimary:
      ++stats_.primary_rays;
      stats_.primary_hits += hit;
      break;
    case RayType::kReflection:
      ++stats_.reflection_rays;
      stats_.reflection_hits += hit;
      break;
    case RayType::kBounce:
      ++stats_.bounce_rays;
      stats_.bounce_hits += hit;
      break;
    case RayType::kShadow: break;
  }
  if (bounces_.empty()) return;
  BounceStats& b = bounces_[info.depth];
  ++b.rays;
  b.hits += hit;
  b.ray_cycles += clock().to_cycles(when) - clock().to_cycles(info.born);
}

void ShadingUnit::retire(uint32_t id, RayType type, Tick when) {
  release();
  back->retire(id, type, when);
}

void ShadingUnit::register_stats(StatsRegistry& r, const std::string& prefix) const {
  register_unit_stats(r, prefix);
  StatsRegistrar v(r, prefix);
  describe_stats(v, stats_);
  for (size_t b = 0; b < bounces_.size(); ++b) {
    StatsRegistrar vb(r, prefix + ".bounce" + std::to_string(b));
    describe_stats(vb, bounces_[b]);
  }
}

}  // namespace rtsim::model
