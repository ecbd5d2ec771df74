#include "model/shadow_culling_unit.h"

#include "model/record_fetch.h"

namespace rtsim::model {

ShadowCullingUnit::ShadowCullingUnit(sc_core::sc_module_name name, const ModelContext& ctx, bool culling, Cache* l1,
                                     FrameBuffer* frame, std::vector<RayFifo*> trv_inputs)
    : Unit(name, ctx.clock), ctx_(ctx), culling_(culling), l1_(l1), frame_(frame), inputs_(std::move(trv_inputs)),
      lights_(ctx.header.light_count) {}

void ShadowCullingUnit::start(Tick now) {
  started_ = true;
  pixel_ = 0;
  light_ = 0;
  if (ctx_.header.light_count == 0) pixel_ = frame_->pixels.size();
  while (pixel_ < frame_->pixels.size() && frame_->pixels[pixel_].hit.tri == kNoHit) ++pixel_;
  wake(now);
}

// The next (hit pixel, light) pair.
void ShadowCullingUnit::advance() {
  if (++light_ < ctx_.header.light_count) return;
  light_ = 0;
  do ++pixel_;
  while (pixel_ < frame_->pixels.size() && frame_->pixels[pixel_].hit.tri == kNoHit);
}

bool ShadowCullingUnit::cycle(Tick now) {
  if (!started_ || finished() || waiting_) return false;
  // The LVB check is a bitwise test on the hit's whole word: culled lights cost no cycle, the
  // unit emits the next shadow ray that is not culled.
  bool culled_any = false;
  while (culling_ && !finished() && !((frame_->pixels[pixel_].lvb >> light_) & 1u)) {
    ++lights_[light_].decisions;
    ++lights_[light_].culled;
    frame_->pixels[pixel_].culled |= uint16_t(1u << light_);
    culled_any = true;
    advance();
  }
  if (finished()) return culled_any;
  PixelState& px = frame_->pixels[pixel_];
  LightStats& ls = lights_[light_];
  if (ctx_.pool->full()) return culled_any;  // woken when a ray retires
  RayFifo* f = inputs_.next_free();
  if (!f) return culled_any;  // woken when a TRV input frees a slot
  const uint64_t addr = ctx_.header.lights.base + uint64_t(light_) * image::kLightBytes;
  const RecordFetch fl = fetch_record(*l1_, addr, image::kLightBytes, now, this, 0);
  if (fl.ready == kUnknown) {
    waiting_ = true;  // keeps the pair: the light record is on its way
    return true;
  }
  uint8_t bytes[image::kLightBytes];
  read_record(*l1_, addr, image::kLightBytes, bytes);
  const image::LightRecord light = image::decode_light(bytes);
  const uint32_t id = ctx_.pool->allocate();
  RayState& r = (*ctx_.pool)[id];
  r.type = RayType::kShadow;
  r.pixel = uint32_t(pixel_);  // the frame entry (pixel and bounce)
  r.light = uint8_t(light_);
  r.trav.ray = shadow_ray(px.surface, light.position, ctx_.shadow_offset);
  f->push(id, std::max(fl.ready, now + clock().period()), now);
  ++ls.decisions;
  ++ls.generated;
  advance();
  return true;
}

Tick ShadowCullingUnit::next_ready(Tick from) const {
  if (!started_ || finished() || waiting_) return kUnknown;
  if (ctx_.pool->full()) return kUnknown;  // woken when a ray retires
  return inputs_.any_free() ? from : kUnknown;  // woken when a TRV input frees a slot
}

uint64_t ShadowCullingUnit::generated() const {
  uint64_t n = 0;
  for (const LightStats& l : lights_) n += l.generated;
  return n;
}

void ShadowCullingUnit::register_stats(StatsRegistry& r, const std::string& prefix) const {
  register_unit_stats(r, prefix);
  for (size_t i = 0; i < lights_.size(); ++i) {
    const std::string p = prefix + ".light" + std::to_string(i);
    r.counter(p + ".decisions", &lights_[i].decisions, "hit pixels considered");
    r.counter(p + ".generated", &lights_[i].generated, "shadow rays emitted");
    r.counter(p + ".culled", &lights_[i].culled, "shadow rays culled by the LVB");
  }
}

}  // namespace rtsim::model
