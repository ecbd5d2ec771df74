// Today's memory topology, stated as data for the memory layer (which names no unit): per unit
// type one L2 shared by its units, or a private L2 per unit (`l2.sharing`); the shading units'
// L1s, and the culling unit's own L1, on the IST's shared L2 (or, when the IST's L2s are
// private, on an L2 of their own with the IST's configuration); the memory crossbar's sources
// in that order; one frame-buffer writer per shading unit and the culling unit's record reader.
#include "model/accelerator_topology.h"

namespace rtsim::model {

namespace {

// Adds a unit type's L2s (one shared, or one per unit) and says where each unit's caches reach.
// Returns the shared L2's index, or the L2 count when they are private.
size_t add_type(MemorySystemConfig& m, const std::string& key, const UnitTypeConfig& u,
                std::vector<MemoryAttachment>& at) {
  if (u.l2_sharing == L2Sharing::kUnit) {
    for (uint32_t i = 0; i < u.count; ++i) {
      at.push_back({m.l2s.size(), 0, true});
      m.l2s.push_back({key + std::to_string(i), u.l2, u.link, {}});
    }
    return m.l2s.size();
  }
  for (uint32_t i = 0; i < u.count; ++i) at.push_back({m.l2s.size(), i, false});
  m.l2s.push_back({key, u.l2, u.link, std::vector<std::string>(u.count, key)});
  return m.l2s.size() - 1;
}

}  // namespace

MemoryTopology memory_topology(const AcceleratorConfig& cfg, MemoryTarget target) {
  MemoryTopology t;
  MemorySystemConfig& m = t.memory;
  m.memory_link = cfg.memory_link;
  m.write_buffer = cfg.write_buffer;
  m.dram = cfg.memory_dram();
  m.loosely_timed_memory = target == MemoryTarget::kLooselyTimed;
  for (uint32_t s = 0; s < cfg.shading.count; ++s)
    m.writers.push_back("shading" + std::to_string(s));
  m.reader = "culling";
  add_type(m, "trv", cfg.trv, t.trv);
  add_type(m, "list", cfg.list, t.list);
  size_t l2 = add_type(m, "ist", cfg.ist, t.ist);
  if (l2 == m.l2s.size()) m.l2s.push_back({"shading", cfg.ist.l2, cfg.ist.link, {}});
  std::vector<std::string>& clients = m.l2s[l2].clients;
  for (uint32_t s = 0; s < cfg.shading.count; ++s) {
    t.shading.push_back({l2, uint32_t(clients.size()), false});
    clients.push_back("shading");
  }
  if (cfg.culling.l1 == CullingL1::kOwn) {
    t.culling = {l2, uint32_t(clients.size()), false};
    clients.push_back("culling");
  }
  return t;
}

}  // namespace rtsim::model
