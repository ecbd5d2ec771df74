#include "model/units/list_unit.h"

#include "model/memory/record_fetch.h"

namespace rtsim::model {

ListUnit::ListUnit(sc_core::sc_module_name name, const ModelContext& ctx, const RayUnitConfig& cfg,
                   MemorySystem& memory, uint32_t index, RayFifo* to_ist)
    : RayUnit(name, ctx, cfg, memory, MemorySystem::kList, index),
      latency_(cfg.latency),
      to_ist_(to_ist) {}

void ListUnit::process(uint32_t id, Tick now) {
  RayState& r = (*ctx_.pool)[id];
  const image::Header& h = ctx_.header;
  if (r.prim_count == 0) {  // first the leaf record
    const uint64_t addr = h.leaves.base + uint64_t(r.trav.leaf) * image::kLeafBytes;
    uint8_t bytes[image::kLeafBytes];
    const Tick ready = load(l1(), id, addr, image::kLeafBytes, bytes, now);
    if (ready == kUnknown) return;
    const image::LeafRecord leaf = image::decode_leaf(bytes);
    ++stats_.leaves;
    r.prim_offset = leaf.prim_offset;
    r.prim_count = leaf.prim_count;
    r.leaf_lvb = leaf.lvb;  // the LVB updater takes it when a hit in this leaf becomes the closest
    r.prims_fetched = 0;
    keep(id, std::max(ready, now) + ctx_.clock.cycles(latency_));
    return;
  }
  // Then the primitive list, one line at a time.
  const uint64_t line_bytes = l1().config().line_bytes;
  const uint64_t addr =
      h.prims.base + uint64_t(r.prim_offset + r.prims_fetched) * image::kPrimBytes;
  const uint64_t line = addr & ~(line_bytes - 1);
  const uint32_t in_line = uint32_t(std::min<uint64_t>(
      (line + line_bytes - addr) / image::kPrimBytes, r.prim_count - r.prims_fetched));
  const RecordFetch f = fetch(l1(), id, line, uint32_t(line_bytes), now);
  if (f.ready == kUnknown) return park(id, f.pending);
  const Tick t = f.ready;
  ++stats_.list_lines;
  const uint8_t* data = l1().line_data(line) + (addr - line);
  for (uint32_t k = 0; k < in_line; ++k)
    r.tris.push_back(image::load_u32(data + k * image::kPrimBytes));
  r.prims_fetched += in_line;
  stats_.prims += in_line;
  const Tick done_at = std::max(t, now) + ctx_.clock.cycles(latency_);
  if (r.prims_fetched < r.prim_count)
    keep(id, done_at);
  else
    emit(to_ist_, id, done_at, now);
}

void ListUnit::register_stats(StatsRegistry& r, const std::string& prefix) const {
  register_unit_stats(r, prefix);
  r.counter(prefix + ".leaves", &stats_.leaves, "count", "leaf records fetched");
  r.counter(prefix + ".list_lines", &stats_.list_lines, "count", "primitive-list lines fetched");
  r.counter(prefix + ".prims", &stats_.prims, "count", "primitive ids read");
}

}  // namespace rtsim::model
