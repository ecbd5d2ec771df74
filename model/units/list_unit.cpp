#include "model/units/list_unit.h"

namespace rtsim::model {

ListUnit::ListUnit(sc_core::sc_module_name name, const ModelContext& ctx, const UnitTypeConfig& cfg)
    : RayUnit(name, ctx, cfg, kListStage, "list"), to_ist("to_ist", this), latency_(cfg.latency) {}

void ListUnit::admitted(uint32_t ray) {
  // A new leaf (TRV sends a ray here once per leaf).
  ListState& l = ray_state(ray).list;
  l.prim_count = 0;
  l.prims_fetched = 0;
  l.tris.clear();
}

void ListUnit::process(uint32_t id, Tick now) {
  RayState& r = ray_state(id);
  ListState& l = r.list;
  const image::Header& h = ctx_.header;
  if (l.prim_count == 0) {  // first the leaf record (a non-empty leaf's)
    const uint32_t index = r.trv.leaf_walk(ctx_.bvh).leaf;
    if (index >= h.leaves.count) return fault_out(id, ImageFault::kLeafIndex, now);
    const uint64_t addr = h.leaves.base + uint64_t(index) * image::kLeafBytes;
    uint8_t bytes[image::kLeafBytes];
    const Tick ready = load(l1(), id, addr, image::kLeafBytes, bytes, now);
    if (ready == kUnknown) return;
    const image::LeafRecord leaf = image::decode_leaf(bytes);
    ++stats_.leaves;
    // The walk sends a ray to non-empty leaves only; the list must lie in its section.
    if (leaf.prim_count == 0 || uint64_t(leaf.prim_offset) + leaf.prim_count > h.prims.count)
      return fault_out(id, ImageFault::kPrimRange, now);
    l.prim_offset = leaf.prim_offset;
    l.prim_count = leaf.prim_count;
    l.leaf_lvb = leaf.lvb;  // the LVB updater takes it when a hit here becomes the closest
    keep(id, std::max(ready, now) + ctx_.clock.cycles(latency_));
    return;
  }
  // Then the primitive list, one line at a time.
  const uint64_t line_bytes = l1().config().line_bytes;
  const uint64_t addr =
      h.prims.base + uint64_t(l.prim_offset + l.prims_fetched) * image::kPrimBytes;
  const uint64_t line = addr & ~(line_bytes - 1);
  const uint32_t in_line = uint32_t(std::min<uint64_t>(
      (line + line_bytes - addr) / image::kPrimBytes, l.prim_count - l.prims_fetched));
  const RecordFetch f = fetch(l1(), id, line, uint32_t(line_bytes), now);
  if (f.ready == kUnknown) return park(id, f.pending);
  ++stats_.list_lines;
  const uint8_t* data = line_data(id, line) + (addr - line);
  for (uint32_t k = 0; k < in_line; ++k)
    l.tris.push_back(image::load_u32(data + k * image::kPrimBytes));
  l.prims_fetched += in_line;
  stats_.prims += in_line;
  const Tick done_at = std::max(f.ready, now) + ctx_.clock.cycles(latency_);
  if (l.prims_fetched < l.prim_count)
    keep(id, done_at);
  else
    emit(to_ist, id, done_at, now);
}

void ListUnit::fault_out(uint32_t id, ImageFault f, Tick now) {
  fault(id, f);
  emit(to_ist, id, now + ctx_.clock.cycles(latency_), now);  // IST passes it on to shading
}

void ListUnit::register_stats(StatsRegistry& r, const std::string& prefix) const {
  register_unit_stats(r, prefix);
  StatsRegistrar v(r, prefix);
  describe_stats(v, stats_);
}

}  // namespace rtsim::model
