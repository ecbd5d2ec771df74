#include "model/shadow_culling_unit.h"

#include "model/record_fetch.h"

namespace rtsim::model {

ShadowCullingUnit::ShadowCullingUnit(sc_core::sc_module_name name, const ModelContext& ctx, bool culling, Cache* l1,
                                     FrameBuffer* frame, std::vector<RayFifo*> trv_inputs)
    : Unit(name, ctx.clock), ctx_(ctx), culling_(culling), l1_(l1), frame_(frame), inputs_(std::move(trv_inputs)),
      lights_(ctx.header.light_count) {}

void ShadowCullingUnit::scan_all(Tick now) {
  scanning_ = closed_ = true;
  scan_ready_ = now;
  entry_ = 0;
  light_ = 0;
  for (const PixelState& px : frame_->pixels) added_ += px.hit.tri != kNoHit;
  if (ctx_.header.light_count == 0) entry_ = frame_->pixels.size();
  while (entry_ < frame_->pixels.size() && frame_->pixels[entry_].hit.tri == kNoHit) ++entry_;
  wake(now);
}

void ShadowCullingUnit::add(uint32_t entry, Tick ready) {
  if (ctx_.header.light_count == 0) return;
  queue_.push_back({entry, ready});
  ++added_;
  wake(queue_.front().ready);
}

void ShadowCullingUnit::close(Tick now) {
  closed_ = true;
  wake(now);
}

double ShadowCullingUnit::decided_fraction() const {
  return added_ ? double(done_) / double(added_) : 0.0;
}

void ShadowCullingUnit::next_entry() {
  ++done_;
  light_ = 0;
  if (!scanning_) {
    queue_.pop_front();
    return;
  }
  do ++entry_;
  while (entry_ < frame_->pixels.size() && frame_->pixels[entry_].hit.tri == kNoHit);
}

void ShadowCullingUnit::advance() {
  if (++light_ == ctx_.header.light_count) next_entry();
}

bool ShadowCullingUnit::cycle(Tick now) {
  if (!has_work() || waiting_ || current_ready() > now) return false;
  // The LVB check is a bitwise test on the hit's whole word: culled lights cost no cycle, the
  // unit emits the next shadow ray that is not culled.
  bool culled_any = false;
  while (culling_ && has_work() && current_ready() <= now && !((frame_->pixels[current()].lvb >> light_) & 1u)) {
    ++lights_[light_].decisions;
    ++lights_[light_].culled;
    frame_->pixels[current()].culled |= uint16_t(1u << light_);
    culled_any = true;
    advance();
  }
  if (!has_work() || current_ready() > now) return culled_any;
  const uint32_t entry = current();
  PixelState& px = frame_->pixels[entry];
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
  r.pixel = entry;  // the frame entry (pixel and bounce)
  r.light = uint8_t(light_);
  r.trav.ray = shadow_ray(px.surface, light.position, ctx_.shadow_offset);
  f->push(id, std::max(fl.ready, now + clock().period()), now);
  ++ls.decisions;
  ++ls.generated;
  advance();
  return true;
}

Tick ShadowCullingUnit::next_ready(Tick from) const {
  if (!has_work() || waiting_) return kUnknown;  // woken by add() or a fill
  if (ctx_.pool->full()) return kUnknown;        // woken when a ray retires
  if (!inputs_.any_free()) return kUnknown;      // woken when a TRV input frees a slot
  return std::max(from, current_ready());
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
