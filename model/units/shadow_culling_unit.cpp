#include "model/units/shadow_culling_unit.h"

#include "kernels/light_samples.h"
#include "model/memory/record_fetch.h"
#include "model/sim/report.h"

namespace rtsim::model {

ShadowCullingUnit::ShadowCullingUnit(sc_core::sc_module_name name, const ModelContext& ctx,
                                     const CullingConfig& config, const TypeMemoryConfig* own_l1,
                                     FrameBuffer* frame, const HitRecordRegion& region)
    : Unit(name, *ctx.calendar, ctx.clock),
      to_trv("to_trv", this),
      lights("lights"),
      records("records"),
      hits("hits"),
      control("control"),
      ctx_(ctx),
      frame_(frame),
      inputs_(to_trv),
      rate_(config.records_per_cycle),
      prefetch_(std::max<uint32_t>(1, config.prefetch)),
      region_(region) {
  hits.bind(*this);
  control.bind(*this);
  light_stats_.reserve(image::kMaxLights);
  if (ctx.paths()) bounce_stats_.resize(size_t(ctx.path.max_depth) + 1);
  if (config.l1 != CullingL1::kOwn) return;
  if (!own_l1)
    report_error(kReportInternal,
                 std::string(this->name()) + ": an own L1 needs its configuration");
  own_l1_ = std::make_unique<ClientCaches>(*own_l1, false, ctx.clock, this, "culling");
}

void ShadowCullingUnit::begin_frame(bool culling, std::vector<DetailWindow> windows) {
  culling_ = culling;
  if (ctx_.header.light_count > light_stats_.capacity())
    report_error(kReportInternal, std::string(name()) + ": more lights than LVB bits");
  if (light_stats_.size() < ctx_.header.light_count) light_stats_.resize(ctx_.header.light_count);
  register_lights();
  closed_ = waiting_ = scanning_ = false;
  entry_ = requested_ = 0;
  queue_.clear();
  inputs_.restart();
  added_ = done_ = generated_ = 0;
  light_ = sample_ = 0;
  light_latched_ = record_open_ = false;
  plan_ = std::move(windows);
  windows_.clear();
  starts_.clear();
  window_ = 0;
  scan_limit_ = 0;
}

void ShadowCullingUnit::end_of_elaboration() {
  if (own_l1_) own_l1_->connect_below();
  l1_ = lights[0];
  reader_ = records.size() > 0 ? records[0] : nullptr;
}

void ShadowCullingUnit::scan_all(Tick now) {
  scanning_ = closed_ = true;
  scan_ready_ = now;
  light_ = 0;
  windows_ = plan_.empty() ? whole_frame(frame_->pixels.size()) : plan_;
  if (!plan_.empty() && !from_memory())
    report_error(kReportInternal, std::string(name()) +
                                      ": a scan in windows reads the records from memory "
                                      "(records_per_cycle > 0)");
  starts_.assign(windows_.size(), {});
  window_ = 0;
  entry_ = windows_[0].begin;
  scan_limit_ = windows_[0].end;
  for (const PixelState& px : frame_->pixels) added_ += px.hit.tri != kNoHit;
  if (ctx_.header.light_count == 0) {
    entry_ = scan_limit_ = frame_->pixels.size();
    windows_ = whole_frame(entry_);
    starts_.assign(1, {});
  }
  if (from_memory()) {
    arrival_.assign(prefetch_, kUnknown);
    prefetched_.assign(prefetch_, HitRecord{});
    requested_ = entry_;
  } else if (rate_ == 0) {
    while (entry_ < frame_->pixels.size() && frame_->pixels[entry_].hit.tri == kNoHit) ++entry_;
  }
  mark_batches(now);
  wake(now);
}

void ShadowCullingUnit::mark_batches(Tick now) {
  if (!scanning_) return;
  std::vector<Tick>& starts = starts_[window_];
  const uint64_t first = windows_[window_].begin / kBatchRays;
  const uint64_t end = std::min(entry_ + 1, frame_->pixels.size());
  while ((first + starts.size()) * kBatchRays < end) starts.push_back(now);
}

bool ShadowCullingUnit::next_window(Tick now) {
  if (window_ + 1 >= windows_.size() || ctx_.pool->in_flight() > 0) return false;
  const DetailWindow& w = windows_[++window_];
  entry_ = requested_ = w.begin;
  scan_limit_ = w.end;
  arrival_.assign(prefetch_, kUnknown);
  mark_batches(now);
  return true;
}

void ShadowCullingUnit::hit_shaded(uint32_t entry, Tick ready) {
  if (ctx_.header.light_count == 0) return;
  queue_.push_back({entry, ready});
  ++added_;
  wake(queue_.front().ready);
}

void ShadowCullingUnit::close(Tick now) {
  closed_ = true;
  wake(now);
}

void ShadowCullingUnit::on_fill(uint64_t, uint64_t cookie, Tick when) {
  if (cookie == 0) {
    waiting_ = false;
  } else {
    // The record's bytes as they arrive (the window keeps its slot until the entry is taken).
    const uint32_t entry = uint32_t(cookie - 1);
    arrival_[entry % prefetch_] = when;
    prefetched_[entry % prefetch_] =
        decode_hit_record(reader_->line_data(region_.slot_address(entry)));
    if (entry != entry_) return;
  }
  wake(when);
}

double ShadowCullingUnit::decided_fraction() const {
  return added_ ? double(done_) / double(added_) : 0.0;
}

Tick ShadowCullingUnit::current_ready() const {
  if (!scanning_) return queue_.front().ready;
  return from_memory() ? arrival_[entry_ % prefetch_] : scan_ready_;
}

void ShadowCullingUnit::next_entry() {
  light_ = 0;
  sample_ = 0;
  light_latched_ = false;
  record_open_ = false;
  if (!scanning_) {
    ++done_;
    queue_.pop_front();
    return;
  }
  if (from_memory()) {
    done_ += record_.hit;
    arrival_[entry_ % prefetch_] = kUnknown;
    ++entry_;
    return;
  }
  ++done_;
  if (rate_ > 0) {
    ++entry_;
    return;
  }
  do ++entry_;
  while (entry_ < frame_->pixels.size() && frame_->pixels[entry_].hit.tri == kNoHit);
}

std::array<LightStats*, 2> ShadowCullingUnit::counted() {
  LightStats* bounce =
      bounce_stats_.empty() ? &scratch_ : &bounce_stats_[frame_->level_of(current())];
  return {&light_stats_[light_], bounce};
}

void ShadowCullingUnit::advance() {
  if (++sample_ < ctx_.light_samples[light_]) return;
  next_light();
}

void ShadowCullingUnit::next_light() {
  sample_ = 0;
  light_latched_ = false;
  if (++light_ == ctx_.header.light_count) next_entry();
}

void ShadowCullingUnit::cull_light() {
  // Every sample of the light: none is generated, all count as unoccluded.
  const uint32_t n = ctx_.light_samples[light_];
  for (LightStats* s : counted()) {
    s->decisions += n;
    s->culled += n;
  }
  frame_->pixels[current()].culled |= uint16_t(1u << light_);
  next_light();
}

bool ShadowCullingUnit::latch_light(Tick now) {
  const uint64_t addr = ctx_.header.lights.base + uint64_t(light_) * image::kLightBytes;
  const RecordFetch fl = fetch_record(*l1_, addr, image::kLightBytes, now, this, 0);
  if (fl.ready == kUnknown) return false;
  uint8_t bytes[image::kLightBytes];
  read_record(*l1_, addr, image::kLightBytes, bytes);
  image::LightRecord light = image::decode_light(bytes);
  Tick ready = fl.ready;
  if (light.area) {
    // Its edges are in its second record (docs/memory-image.md).
    const uint64_t area_addr =
        ctx_.header.lights.base + uint64_t(ctx_.header.light_count + light_) * image::kLightBytes;
    const RecordFetch fa = fetch_record(*l1_, area_addr, image::kLightBytes, now, this, 0);
    if (fa.ready == kUnknown) return false;
    read_record(*l1_, area_addr, image::kLightBytes, bytes);
    image::decode_light_area(bytes, light);
    ready = std::max(ready, fa.ready);
  }
  latched_ = light;
  latched_ready_ = ready;
  light_latched_ = true;
  return true;
}

bool ShadowCullingUnit::emit(const SurfacePoint& surface, Tick now) {
  if (ctx_.pool->full()) return false;  // woken when a ray retires
  RayQueueIn* f = inputs_.next_free();
  if (!f) return false;  // woken when a TRV input frees a slot
  if (!light_latched_ && !latch_light(now)) {
    waiting_ = true;  // keeps the pair: a light record is on its way
    return true;
  }
  const image::LightRecord& light = latched_;
  const uint32_t entry = current();  // the frame entry (pixel and bounce)
  RayInfo info;
  info.type = RayType::kShadow;
  info.entry = entry;
  info.light = uint8_t(light_);
  info.sample = uint16_t(sample_);
  info.depth = uint8_t(frame_->level_of(entry));
  info.born = now;
  info.ray = shadow_ray(
      surface,
      light_sample_point(light, frame_->pixel_of(entry), frame_->key_of(entry), light_, sample_),
      ctx_.shadow_offset);
  const uint32_t id = ctx_.pool->create(info);
  f->push(id, std::max(latched_ready_, now + clock().period()), now);
  for (LightStats* s : counted()) {
    ++s->decisions;
    ++s->generated;
  }
  ++generated_;
  advance();
  return true;
}

bool ShadowCullingUnit::cycle(Tick now) {
  if (scanning_ && entry_ == scan_limit_ && !next_window(now)) return false;
  const bool active = rate_ == 0 ? cycle_unlimited(now) : cycle_limited(now);
  mark_batches(now);
  return active;
}

bool ShadowCullingUnit::cycle_unlimited(Tick now) {
  if (!in_window() || waiting_ || current_ready() > now) return false;
  // The LVB check is a bitwise test on the hit's whole word: culled lights cost no cycle, the
  // unit emits the next shadow ray that is not culled.
  bool culled_any = false;
  while (culling_ && in_window() && current_ready() <= now &&
         !((frame_->pixels[current()].lvb >> light_) & 1u)) {
    cull_light();
    culled_any = true;
  }
  if (!in_window() || current_ready() > now) return culled_any;
  return emit(frame_->pixels[current()].surface, now) || culled_any;
}

bool ShadowCullingUnit::request_records(Tick now) {
  bool any = false;
  for (uint32_t k = 0; k < rate_ && can_request(); ++k) {
    const uint32_t entry = uint32_t(requested_++);  // a record slot
    ++stats_.record_reads;
    const Tick t = reader_->fetch_line(region_.slot_address(entry), now, this, uint64_t(entry) + 1);
    arrival_[entry % prefetch_] = t;
    if (t != kUnknown)
      prefetched_[entry % prefetch_] =
          decode_hit_record(reader_->line_data(region_.slot_address(entry)));
    any = true;
  }
  return any;
}

bool ShadowCullingUnit::cycle_limited(Tick now) {
  const bool requested = request_records(now);
  uint32_t taken = 0;
  while (in_window() && !waiting_ && current_ready() <= now) {
    if (!record_open_) {  // a new record: it takes one of this cycle's slots
      if (taken == rate_) break;
      ++taken;
      ++stats_.records_taken;
      record_open_ = true;
      if (from_memory()) {
        record_ = prefetched_[entry_ % prefetch_];
      } else {
        const PixelState& px = frame_->pixels[current()];
        record_ = {px.surface, px.lvb, px.hit.tri != kNoHit};
      }
    }
    if (!record_.hit) {
      next_entry();
      continue;
    }
    if (culling_ && !((record_.lvb >> light_) & 1u)) {
      cull_light();
      continue;
    }
    return emit(record_.surface, now) || requested || taken > 0;  // one ray per cycle
  }
  return requested || taken > 0;
}

Tick ShadowCullingUnit::next_ready(Tick from) const {
  if (scanning_ && entry_ == scan_limit_)  // between windows: when the last ray in flight retires
    return window_ + 1 < windows_.size() && ctx_.pool->in_flight() == 0 ? from : kUnknown;
  if (rate_ > 0 && can_request()) return from;    // keep the reads flowing
  if (!in_window() || waiting_) return kUnknown;  // woken by hit_shaded() or a fill
  if (ctx_.pool->full()) return kUnknown;         // woken when a ray retires
  if (!inputs_.any_free()) return kUnknown;       // woken when a TRV input frees a slot
  const Tick ready = current_ready();
  return ready == kUnknown ? kUnknown : std::max(from, ready);
}

std::string ShadowCullingUnit::state() const {
  std::string s =
      "culling unit: " + std::to_string(done_) + " of " + std::to_string(added_) + " hits decided";
  if (!has_work()) return s + (closed_ ? ", done" : ", waiting for hits");
  if (!in_window()) return s + ", between windows";
  s += ", at entry " + std::to_string(current()) + " light " + std::to_string(light_);
  if (ctx_.light_samples[light_] > 1) s += " sample " + std::to_string(sample_);
  if (waiting_) s += ", waiting for a light record";
  const Tick ready = current_ready();
  s += ready == kUnknown ? ", its record not arrived"
                         : ", its record ready at " + std::to_string(ready) + " ps";
  if (from_memory()) s += ", " + std::to_string(requested_) + " records asked for";
  return s;
}

uint64_t ShadowCullingUnit::generated() const { return generated_; }

void ShadowCullingUnit::register_stats(StatsRegistry& r, const std::string& prefix) {
  register_unit_stats(r, prefix);
  StatsRegistrar v(r, prefix);
  describe_stats(v, stats_);
  registry_ = &r;
  prefix_ = prefix;
  register_lights();
  for (size_t b = 0; b < bounce_stats_.size(); ++b) {
    StatsRegistrar vb(r, prefix + ".bounce" + std::to_string(b));
    describe_stats(vb, bounce_stats_[b]);
  }
}

void ShadowCullingUnit::register_lights() {
  if (!registry_) return;
  for (; registered_lights_ < light_stats_.size(); ++registered_lights_) {
    const size_t i = registered_lights_;
    StatsRegistrar v(*registry_, prefix_ + ".light" + std::to_string(i));
    describe_stats(v, light_stats_[i]);
  }
}

}  // namespace rtsim::model
