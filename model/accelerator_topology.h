// The accelerator's memory topology as data (model/accelerator_topology.cpp): which L2s sit on the
// memory crossbar, and which one each unit's own caches reach. The memory layer
// (model/memory/memory_system.h) builds what this says and names no unit.
#pragma once

#include "model/accelerator.h"
#include "model/accelerator_config.h"
#include "model/memory/memory_system.h"
#include "model/units/ray_state.h"

#include <array>

#include <vector>

namespace rtsim::model {

// Where a client's own caches reach below (MemorySystem): source `source` of shared L2 `l2`, or,
// when the client's L2 is private, L2 `l2`'s way to memory.
struct MemoryAttachment {
  size_t l2 = 0;
  uint32_t source = 0;
  bool private_l2 = false;
};

// The memory topology as data (model/accelerator_topology.cpp): the L2s on the memory crossbar and
// which one each unit's caches reach.
struct MemoryTopology {
  MemorySystemConfig memory;
  std::array<std::vector<MemoryAttachment>, kStages> units;  // by type (stage), then unit index
  MemoryAttachment culling;                                  // its own L1's, when it has one
};
MemoryTopology memory_topology(const AcceleratorConfig& cfg, MemoryTarget target);

// The ray path's fan-in, as data: unit `i` of a stage of `from` units hands its rays to unit
// i x to / from of the next stage of `to` units (TRV -> LIST, LIST -> IST, TRV -> shading).
inline uint32_t fan_in(uint32_t i, uint32_t from, uint32_t to) {
  return uint32_t(uint64_t(i) * to / from);
}
// The units a ray dealt to traversal unit `t` visits, by stage: the path bind_ray_path binds, which
// the sampled frame's warming and functional pass follow too.
std::array<uint32_t, kStages> ray_route(const AcceleratorConfig& cfg, uint32_t t);

// What a client attached at `a` binds its mem_side to.
inline LineSource& reach(MemorySystem& memory, const MemoryAttachment& a) {
  return a.private_l2 ? memory.memory_port(a.l2) : memory.client_port(a.l2, a.source);
}

}  // namespace rtsim::model
