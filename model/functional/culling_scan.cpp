// The shadow phase's source of rays in the functional pass's replay: the culling unit's scan over
// the record slots, as model/units/shadow_culling_unit.cpp makes it in two phases with the records
// read from memory (model/functional/batch_features.h says what the replay keeps of its timing).
#include "model/functional/functional_pass.h"

namespace rtsim::model::functional {

void Replay::begin_scan(uint64_t at) {
  next_unit_ = 0;  // the culling unit's round robin over the traversal units' inputs
  scan_ = ScanState{};
  scan_.free = at;
  scan_.last_request = at;
  scan_.left.assign(prefetch_, at);
}

// Slot s is requested once the cursor has left slot s - prefetch, one request a cycle; it comes a
// DRAM read later, and the port takes a line every `line_flits` cycles.
uint64_t Replay::record_arrival() {
  ScanState& s = scan_;
  const uint64_t allowed = s.left[s.slot % prefetch_];  // slot - prefetch left (or the start)
  const uint64_t request = s.slot == 0 ? s.last_request : std::max(s.last_request + 1, allowed);
  const uint64_t arrival =
      std::max(request + machine_.dram_cycles(records_base_ + s.slot * record_stride_),
               s.slot == 0 ? 0 : s.last_arrival + machine_.line_flits());
  s.last_request = request;
  s.last_arrival = arrival;
  return arrival;
}

// The cursor leaves its slot at `t`: the unit takes the next record at `t` at the earliest.
void Replay::leave(uint64_t t) {
  scan_.left[scan_.slot % prefetch_] = t;
  scan_.free = t;
  scan_.open = false;
  ++scan_.slot;
}

bool Replay::take_record() {
  ScanState& s = scan_;
  if ((s.slot / kBatchRays) % shadow_stride_ != 0) {  // a batch passed over
    if (s.slot % kBatchRays == 0) starts_[kShadow].push_back(s.free);
    scan_batch().hits += hits_[s.slot].tri != kNoHit;
    leave(s.free);
    return false;
  }
  const uint64_t t = std::max(s.free, record_arrival());
  if (s.slot % kBatchRays == 0) starts_[kShadow].push_back(t);
  const Hit& hit = hits_[s.slot];
  if (hit.tri == kNoHit) {
    leave(t + 1);  // a record without a hit takes its cycle too
    return false;
  }
  ++scan_batch().hits;
  s.lvb = image_.leaf(hit.leaf).lvb;  // the ray itself is built with its walk (Walks)
  s.open = true;
  s.taken = s.free = t;
  s.light = s.sample = 0;
  s.latched = false;
  return true;
}

bool Replay::find_emission() {
  ScanState& s = scan_;
  for (;;) {
    if (!s.open) {
      if (s.slot == order_.size()) return false;
      take_record();
      continue;
    }
    if (s.light == lights_.size()) {
      leave(std::max(s.free, s.taken + 1));
      continue;
    }
    if (culling_ && !((s.lvb >> s.light) & 1u)) {  // culled within the cycle
      scan_batch().culled += lights_[s.light].samples;
      ++s.light;
      continue;
    }
    return true;
  }
}

uint64_t Replay::read_light() {
  const uint32_t i = scan_.light;
  CacheCounts& counts = scan_batch().caches;
  const auto light = [&](uint32_t addr) {
    return machine_.read(0, Access{addr, image::kLightBytes, WalkRead::kLight}, counts);
  };
  int level = light(image_.light_addr(i));
  if (lights_[i].area) level = std::max(level, light(image_.light_area_addr(i)));
  return machine_.read_cycles(kShadingStage, level, image_.light_addr(i));
}

bool Replay::take_shadow(uint64_t now, Queued& q) {
  if (!find_emission()) return false;
  ScanState& s = scan_;
  uint64_t t = std::max(now, s.free);
  if (!s.latched) {
    // The light's record through the culling unit's L1; on a miss the unit waits for it.
    const uint64_t cycles = read_light();
    s.latched = true;
    s.light_ready = t + cycles;
    if (cycles > machine_.timing(kShadingStage).l1_hit) t = s.light_ready;
  }
  const image::LightRecord& light = lights_[s.light];
  q.ray = s.slot;
  q.dealt = t;
  q.ready = std::max(t + 1, s.light_ready);
  TracedRay& r = traced_->next();  // the walk of this (slot, light, sample)
  q.stream = std::move(r.stream);
  scan_batch().occluded += r.occluded;
  ++scan_batch().rays;
  s.free = t + 1;
  if (++s.sample == light.samples) {
    s.sample = 0;
    s.latched = false;
    ++s.light;
  }
  return true;
}

}  // namespace rtsim::model::functional
