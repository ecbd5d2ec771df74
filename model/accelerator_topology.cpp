// The memory topology, stated as data for the memory layer (which names no unit), from the unit
// table (model/accelerator_units.h): per unit type one L2 shared by its units, or a private L2
// per unit (`l2.sharing`), or the L2 of the type its row names (the shading L1s on the IST's; when
// the IST's L2s are private, on an L2 of their own with the IST's configuration); the culling
// unit's own L1 beside the shading L1s; the memory crossbar's sources in the table's order; one
// frame-buffer writer per shading unit and the culling unit's record reader.
#include "model/accelerator_topology.h"

#include "model/accelerator_units.h"

namespace rtsim::model {

namespace {

constexpr size_t kPrivate = ~size_t(0);

// Adds a unit type's L2s (one shared, or one per unit) and says where each unit's caches reach.
// Returns the shared L2's index, or kPrivate.
size_t add_type(MemorySystemConfig& m, const std::string& key, const UnitTypeConfig& u,
                std::vector<MemoryAttachment>& at) {
  if (u.l2_sharing == L2Sharing::kUnit) {
    for (uint32_t i = 0; i < u.count; ++i) {
      at.push_back({m.l2s.size(), 0, true});
      m.l2s.push_back({key + std::to_string(i), u.l2, u.link, {}});
    }
    return kPrivate;
  }
  for (uint32_t i = 0; i < u.count; ++i) at.push_back({m.l2s.size(), i, false});
  m.l2s.push_back({key, u.l2, u.link, std::vector<std::string>(u.count, key)});
  return m.l2s.size() - 1;
}

}  // namespace

std::array<uint32_t, kStages> ray_route(const AcceleratorConfig& cfg, uint32_t t) {
  const uint32_t trv = cfg.traversal().count, list = fan_in(t, trv, cfg.list.count);
  std::array<uint32_t, kStages> route{};
  route[kTrvStage] = t;
  route[kListStage] = list;
  route[kIstStage] = fan_in(list, cfg.list.count, cfg.ist.count);
  route[kShadingStage] = fan_in(t, trv, cfg.shading.count);
  return route;
}

MemoryTopology memory_topology(const AcceleratorConfig& cfg, MemoryTarget target) {
  MemoryTopology t;
  MemorySystemConfig& m = t.memory;
  m.memory_link = cfg.memory_link;
  m.write_buffer = cfg.write_buffer;
  m.dram = cfg.memory_dram();
  m.memory_target = target == MemoryTarget::kBuiltin        ? PortTarget::kOwnCalendar
                    : target == MemoryTarget::kLooselyTimed ? PortTarget::kLooselyTimed
                                                            : PortTarget::kPlatform;
  for (uint32_t s = 0; s < cfg.shading.count; ++s)
    m.writers.push_back("shading" + std::to_string(s));
  m.reader = "culling";
  // A type's own L2s first; then the types on another's L2, which is shared or, when that type's
  // L2s are private, one of their own with its configuration.
  const UnitTypes types = unit_types(cfg);
  std::array<size_t, kStages> shared{};
  for (const RayUnitType* type : types)
    if (type->l2_of == type->stage)
      shared[type->stage] = add_type(m, type->key, cfg.*type->config, t.units[type->stage]);
  for (const RayUnitType* tp : types) {
    const RayUnitType& type = *tp;
    if (type.l2_of == type.stage) continue;
    size_t& l2 = shared[type.l2_of];
    const UnitTypeConfig& host = cfg.*types[type.l2_of]->config;
    if (l2 == kPrivate) {
      l2 = m.l2s.size();
      m.l2s.push_back({type.key, host.l2, host.link, {}});
    }
    std::vector<std::string>& clients = m.l2s[l2].clients;
    for (uint32_t i = 0; i < (cfg.*type.config).count; ++i) {
      t.units[type.stage].push_back({l2, uint32_t(clients.size()), false});
      clients.push_back(type.key);
    }
    if (type.stage == kShadingStage && cfg.culling.l1 == CullingL1::kOwn) {
      t.culling = {l2, uint32_t(clients.size()), false};
      clients.push_back("culling");
    }
  }
  return t;
}

}  // namespace rtsim::model
