// A sampled frame's functional warming (Accelerator::sample, CacheWarmer): the records the skipped
// rays would have read go through the caches of the units that would have read them, as tags and
// LRU order, with the lines' bytes read from the built-in memory's store.
#include "model/accelerator_netlist.h"

#include <cstring>

namespace rtsim::model {

void Accelerator::Netlist::warm_line(Cache& cache, Cache* below, uint64_t addr) {
  const uint32_t bytes = cache.config().line_bytes;
  const uint64_t line = addr & ~uint64_t(bytes - 1);
  const uint32_t piece = cfg.memory_dram().request_bytes;  // the store's unit
  warm_bytes.resize(bytes);
  for (uint32_t o = 0; o < bytes; o += piece)
    std::memcpy(&warm_bytes[o], dram->line_data(line + o), std::min(piece, bytes - o));
  if (cache.warm(line, warm_bytes.data()) || !below) return;
  const uint32_t below_bytes = below->config().line_bytes;
  const uint64_t below_line = addr & ~uint64_t(below_bytes - 1);
  warm_bytes.resize(below_bytes);
  for (uint32_t o = 0; o < below_bytes; o += piece)
    std::memcpy(&warm_bytes[o], dram->line_data(below_line + o), std::min(piece, below_bytes - o));
  below->warm(below_line, warm_bytes.data());
}

void Accelerator::Netlist::read(WalkRead kind, uint32_t traversal, uint64_t addr, uint32_t bytes) {
  const Stage stage = stage_of(kind);
  const uint32_t i = ray_route(cfg, traversal % cfg.traversal().count)[stage];
  RayUnit& u = *units[stage][i];
  const MemoryAttachment& at = topology.units[stage][i];
  Cache* l2 = at.private_l2 ? u.caches().l2() : memory->shared_l2(at.l2);
  const uint32_t line = u.l1().config().line_bytes;
  for (uint64_t a = addr & ~uint64_t(line - 1); a < addr + bytes; a += line)
    warm_line(u.l1(), l2, a);
}

}  // namespace rtsim::model
