#include "model/units/bvh_unit.h"

#include <algorithm>

namespace rtsim::model {

namespace {

// Every BVH format numbers a node's inner children after it (pre-order, or cwbvh8's
// breadth-first records; docs/memory-image.md; kernels/bvh_format.h requires it): a child at or
// before its parent is not an image.
bool children_after(const BvhNodeView& n, uint32_t node) {
  for (uint32_t i = 0; i < n.count; ++i)
    if (!n.leaf[i] && n.ref[i] <= node) return false;
  return true;
}

}  // namespace

BvhUnit::BvhUnit(sc_core::sc_module_name name, const ModelContext& ctx, const UnitTypeConfig& cfg,
                 const BvhWalkConfig& walk, uint32_t index)
    : TraversalUnit(name, ctx, cfg, index, "bvh"),
      latency_(cfg.latency),
      walk_(walk),
      slots_(cfg.capacity) {
  for (Slot& s : slots_) s.stack.resize(kBvhStackEntries);
  for (uint32_t i = cfg.capacity; i-- > 0;) free_slots_.push_back(uint16_t(i));
}

void BvhUnit::owned(uint32_t ray) {
  // can_admit() kept the owned rays below the capacity: a slot is free.
  ray_state(ray).trv.stack_slot = free_slots_.back();
  free_slots_.pop_back();
}

void BvhUnit::released(uint32_t ray) { free_slots_.push_back(ray_state(ray).trv.stack_slot); }

void BvhUnit::account_pushes(TrvState& t, uint32_t pushed) {
  stats_.stack_pushes += pushed;
  t.on_chip = uint16_t(t.on_chip + pushed);
  if (walk_.stack_entries > 0 && t.on_chip > walk_.stack_entries) {
    stats_.stack_spills += t.on_chip - walk_.stack_entries;
    t.on_chip = uint16_t(walk_.stack_entries);
  }
}

Tick BvhUnit::account_pops(TrvState& t, uint32_t popped) {
  stats_.stack_pops += popped;
  Tick extra = 0;
  for (uint32_t k = 0; k < popped; ++k) {
    if (t.on_chip == 0) {
      // All the entries left are spilled: a batch of them comes back on chip.
      const uint32_t spilled = t.bvh.sp + (popped - k);
      t.on_chip = uint16_t(std::min(spilled, walk_.stack_entries));
      ++stats_.stack_refills;
      extra += ctx_.clock.cycles(walk_.spill_latency);
    }
    --t.on_chip;
  }
  return extra;
}

bool BvhUnit::leaf_done(uint32_t ray, Tick when) {
  RayState& r = ray_state(ray);
  TrvState& t = r.trv;
  const TraversalStep step = bvh_traversal_pop(t.bvh, r.ist.result);
  const Tick extra = account_pops(t, t.bvh.skipped + (step != TraversalStep::kDone));
  if (step == TraversalStep::kDone) return false;
  t.leaf_next = step == TraversalStep::kLeaf;  // the popped leaf goes to LIST from here
  take_back(ray, when + extra);
  return true;
}

void BvhUnit::process(uint32_t id, Tick now) {
  RayState& r = ray_state(id);
  TrvState& t = r.trv;
  if (!t.started) {
    t.started = true;
    t.on_chip = 0;
    t.leaf_next = false;
    t.node_chunk = 0;
    t.steps = 0;
    ++stats_.rays_started;
    const bool any_hit = r.info.type == RayType::kShadow;
    if (!bvh_traversal_begin(t.bvh, r.info.ray, any_hit, ctx_.header.bounds, ctx_.abs_eps,
                             slots_[t.stack_slot].stack.data())) {
      ++stats_.rays_done;
      emit(to_shading, id, now + ctx_.clock.cycles(latency_), now);  // misses the scene
      return;
    }
  }
  if (t.leaf_next) {  // one cycle to read the popped entry
    t.leaf_next = false;
    ++stats_.leaves;
    emit(to_list, id, now + ctx_.clock.period(), now);
    return;
  }
  node_operation(id, now);
}

void BvhUnit::node_operation(uint32_t id, Tick now) {
  RayState& r = ray_state(id);
  TrvState& t = r.trv;
  BvhTraversalState& walk = t.bvh;
  Slot& slot = slots_[t.stack_slot];
  const image::Header& h = ctx_.header;
  const uint32_t node_bytes = h.node_bytes();
  const uint32_t chunk = 2 * l1().line_bytes();  // what one operation reads: two L1 lines
  const uint32_t chunks = (node_bytes + chunk - 1) / chunk;
  const uint32_t op = t.node_chunk;
  if (op == 0 && !fetchable(id, walk.node, now + ctx_.clock.cycles(latency_), now)) {
    ++stats_.rays_done;
    return;
  }
  if (op < chunks) {
    const uint32_t offset = op * chunk;
    const uint64_t addr = h.nodes.base + uint64_t(walk.node) * node_bytes + offset;
    const Tick ready =
        load(l1(), id, addr, std::min(chunk, node_bytes - offset), slot.node + offset, now);
    if (ready == kUnknown) return;  // parked; this operation issues again when its line is in
    slot.node_ready = op == 0 ? ready : std::max(slot.node_ready, ready);
  }
  ++stats_.node_operations;
  if (op + 1 < chunks) {
    t.node_chunk = uint8_t(op + 1);
    keep(id, now + ctx_.clock.period());
    return;
  }
  const BvhNodeFormat& format = *ctx_.bvh_format;  // the image's, looked up with its header
  const BvhNodeView node = format.decode(slot.node);
  const uint32_t passes = std::max<uint32_t>(
      1, (node.count + walk_.box_tests_per_cycle - 1) / walk_.box_tests_per_cycle);
  if (op + 1 < passes) {  // more boxes than one operation tests
    t.node_chunk = uint8_t(op + 1);
    keep(id, now + ctx_.clock.period());
    return;
  }
  t.node_chunk = 0;
  ++stats_.node_fetches;
  ++stats_.node_fetches_by[size_t(r.info.type)];
  ++t.steps;
  stats_.box_tests += node.count;
  const uint32_t parent = walk.node;  // the step moves it on
  const TraversalStep step = bvh_traversal_node(walk, r.ist.result, node);
  if (step == TraversalStep::kFault || !children_after(node, parent)) {
    ++stats_.rays_done;
    const ImageFault f =
        step == TraversalStep::kFault ? ImageFault::kStackOverflow : ImageFault::kNodeIndex;
    return walk_fault(id, f, now + ctx_.clock.cycles(latency_), now);
  }
  // The nearest hit child goes straight on; the other hit children go on the stack. Without a
  // hit child the ray pops (skipping entries beyond its best hit).
  Tick extra = 0;
  if (walk.pushed > 0)
    account_pushes(t, walk.pushed - 1);
  else
    extra = account_pops(t, walk.skipped + (step != TraversalStep::kDone));
  const uint32_t decode = format.traits().decode_cycles ? walk_.decode_latency : 0;
  const Tick done_at =
      std::max(slot.node_ready, now) + ctx_.clock.cycles(latency_ + decode) + extra;
  switch (step) {
    case TraversalStep::kFetchNode: keep(id, done_at); break;
    case TraversalStep::kLeaf:
      ++stats_.leaves;
      emit(to_list, id, done_at, now);
      break;
    case TraversalStep::kDone:
    case TraversalStep::kFault:  // handled above
      ++stats_.rays_done;
      emit(to_shading, id, done_at, now);
      break;
  }
}

void BvhUnit::register_stats(StatsRegistry& r, const std::string& prefix) const {
  register_unit_stats(r, prefix);
  StatsRegistrar v(r, prefix);
  describe_stats(v, stats_);
}

}  // namespace rtsim::model
