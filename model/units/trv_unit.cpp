#include "model/units/trv_unit.h"

namespace rtsim::model {

TrvUnit::TrvUnit(sc_core::sc_module_name name, const ModelContext& ctx, const UnitTypeConfig& cfg,
                 uint32_t index)
    : TraversalUnit(name, ctx, cfg, index, "trv"), latency_(cfg.latency) {}

bool TrvUnit::leaf_done(uint32_t ray, Tick when) {
  RayState& r = ray_state(ray);
  if (traversal_pop(r.trv.walk, r.ist.result) != TraversalStep::kFetchNode) return false;
  take_back(ray, when);
  return true;
}

void TrvUnit::process(uint32_t id, Tick now) {
  RayState& r = ray_state(id);
  TraversalState& walk = r.trv.walk;
  if (!r.trv.started) {
    r.trv.started = true;
    r.trv.steps = 0;
    ++stats_.rays_started;
    const bool any_hit = r.info.type == RayType::kShadow;
    if (!traversal_begin(walk, r.info.ray, any_hit, ctx_.header.bounds, ctx_.abs_eps)) {
      ++stats_.rays_done;
      emit(to_shading, id, now + ctx_.clock.cycles(latency_), now);  // misses the scene
      return;
    }
  }
  if (!fetchable(id, walk.node, now + ctx_.clock.cycles(latency_), now)) {
    ++stats_.rays_done;
    return;
  }
  const uint64_t addr = ctx_.header.nodes.base + uint64_t(walk.node) * image::kNodeBytes;
  uint8_t bytes[image::kNodeBytes];
  const Tick ready = load(l1(), id, addr, image::kNodeBytes, bytes, now);
  if (ready == kUnknown) return;  // parked: the fetch counts when the node is read
  ++stats_.node_fetches;
  ++stats_.node_fetches_by[size_t(r.info.type)];
  ++r.trv.steps;
  const KdNode node = image::decode_node(bytes);
  const Tick done_at = std::max(ready, now) + ctx_.clock.cycles(latency_);
  // Nodes are stored depth first (docs/memory-image.md): a child lies after its parent.
  if (!node.is_leaf() && node.above_child() <= walk.node) {
    ++stats_.rays_done;
    return walk_fault(id, ImageFault::kNodeIndex, done_at, now);
  }
  const TraversalStep step = traversal_node(walk, r.ist.result, node);
  switch (step) {
    case TraversalStep::kFetchNode: keep(id, done_at); break;
    case TraversalStep::kLeaf: emit(to_list, id, done_at, now); break;
    case TraversalStep::kDone:
      ++stats_.rays_done;
      emit(to_shading, id, done_at, now);
      break;
    case TraversalStep::kFault:
      ++stats_.rays_done;
      walk_fault(id, ImageFault::kStackOverflow, done_at, now);
      break;
  }
}

void TrvUnit::register_stats(StatsRegistry& r, const std::string& prefix) const {
  register_unit_stats(r, prefix);
  StatsRegistrar v(r, prefix);
  describe_stats(v, stats_);
}

}  // namespace rtsim::model
