#include "model/units/trv_unit.h"

#include "model/memory/record_fetch.h"

namespace rtsim::model {

TrvUnit::TrvUnit(sc_core::sc_module_name name, const ModelContext& ctx, const RayUnitConfig& cfg,
                 MemorySystem& memory, uint32_t index, RayFifo* to_list, RayOwners* owners)
    : RayUnit(name, ctx, cfg, memory, MemorySystem::kTrv, index),
      latency_(cfg.latency),
      capacity_(cfg.capacity),
      index_(uint16_t(index)),
      to_list_(to_list),
      owners_(owners) {}

void TrvUnit::admitted(uint32_t ray) {
  ++owned_;
  (*ctx_.pool)[ray].trv_unit = index_;
}

void TrvUnit::process(uint32_t id, Tick now) {
  RayState& r = (*ctx_.pool)[id];
  if (!r.started) {
    r.started = true;
    ++stats_.rays_started;
    const bool any_hit = r.type == RayType::kShadow;
    if (!traversal_begin(r.trav, r.trav.ray, any_hit, ctx_.header.bounds, ctx_.abs_eps)) {
      ++stats_.rays_done;
      // Misses the scene
      emit(owners_->shading_input(id), id, now + ctx_.clock.cycles(latency_), now);
      return;
    }
  }
  const uint64_t addr = ctx_.header.nodes.base + uint64_t(r.trav.node) * image::kNodeBytes;
  ++stats_.node_fetches;
  uint8_t bytes[image::kNodeBytes];
  const Tick ready = load(l1(), id, addr, image::kNodeBytes, bytes, now);
  if (ready == kUnknown) return;
  const TraversalStep step = traversal_node(r.trav, image::decode_node(bytes));
  const Tick done_at = std::max(ready, now) + ctx_.clock.cycles(latency_);
  switch (step) {
    case TraversalStep::kFetchNode: keep(id, done_at); break;
    case TraversalStep::kLeaf:
      r.prims_fetched = 0;
      r.prim_count = 0;
      r.tests_issued = 0;
      r.leaf_done_at = 0;
      r.tris.clear();
      emit(to_list_, id, done_at, now);
      break;
    case TraversalStep::kDone:
      ++stats_.rays_done;
      emit(owners_->shading_input(id), id, done_at, now);
      break;
  }
}

void TrvUnit::register_stats(StatsRegistry& r, const std::string& prefix) const {
  register_unit_stats(r, prefix);
  r.counter(prefix + ".node_fetches", &stats_.node_fetches, "count", "kd-tree nodes fetched");
  r.counter(prefix + ".rays_started", &stats_.rays_started, "count",
            "rays that began traversal here");
  r.counter(prefix + ".rays_done", &stats_.rays_done, "count", "rays whose traversal ended here");
}

}  // namespace rtsim::model
