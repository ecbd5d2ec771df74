#include "model/memory/memory_system.h"

namespace rtsim::model {

// A unit type's shared level, named after the type: its children are the group's `l2` and `icnt`.
class MemorySystem::TypeModule : public sc_core::sc_module {
 public:
  TypeModule(sc_core::sc_module_name name, MemorySystem& m, Type t, uint32_t l1_sources)
      : sc_core::sc_module(name) {
    group = m.build_group(t, 0, l1_sources);
  }
  L2Group group;
};

const char* MemorySystem::type_name(Type t) {
  static const char* names[kTypes] = {"trv", "list", "ist", "shading", "culling"};
  return names[t];
}

MemorySystem::MemorySystem(const MemorySystemConfig& config, const Clock& clock, Calendar& calendar)
    : cfg_(config), clock_(clock) {
  const MemorySystemConfig& cfg = cfg_;
  // The culling unit's L1 is a shading L1 (and its L2 the shading units').
  const TypeMemoryConfig* unit_cfg[kTypes] = {&cfg.trv, &cfg.list, &cfg.ist, &cfg.shading,
                                              &cfg.shading};
  const uint32_t culling_l1s = cfg.culling_l1 ? 1 : 0;
  const bool ist_private = cfg.ist.l2_sharing == L2Sharing::kUnit;
  // The L2 configuration and the number of L2s of each type (the shading unit has its own L2 only
  // when the IST's are private; otherwise its L1 is one more source on the IST's crossbar).
  uint32_t sources = 0;
  for (int t = 0; t < kTypes; ++t) {
    TypeMemory& m = types_[t];
    m.cfg = unit_cfg[t];
    const bool on_shading_l2 = t == kShading || t == kCulling;
    m.l2_cfg = on_shading_l2 ? &cfg.ist : m.cfg;
    m.private_l2 = on_shading_l2 ? false : m.cfg->l2_sharing == L2Sharing::kUnit;
    uint32_t groups = m.private_l2 ? m.cfg->count : 1;
    if (on_shading_l2) groups = t == kShading && ist_private ? 1 : 0;
    m.first_source = sources;
    sources += groups * m.l2_cfg->l2.banks;
  }
  interconnect_ = std::make_unique<MemoryInterconnect>("memory", cfg.memory_link, cfg.dram, clock,
                                                       calendar, sources, cfg.shading.count,
                                                       cfg.write_buffer, cfg.loosely_timed_memory);
  for (int t = 0; t < kTypes; ++t) {
    TypeMemory& m = types_[t];
    if (m.private_l2 || t == kCulling || (t == kShading && !ist_private)) continue;
    uint32_t l1s = m.cfg->count;  // the sources on its crossbar: its L1s, then the shading ones
    if (t == kIst && !ist_private) l1s += cfg.shading.count + culling_l1s;
    if (t == kShading) l1s += culling_l1s;
    m.shared = std::make_unique<TypeModule>(type_name(Type(t)), *this, Type(t), l1s);
  }
}

MemorySystem::~MemorySystem() = default;

L2Group MemorySystem::build_group(Type t, uint32_t group, uint32_t l1_sources) {
  TypeMemory& m = types_[t];
  const TypeMemoryConfig& lc = *m.l2_cfg;
  L2Group g;
  const std::string owner = m.private_l2 ? type_name(t) + std::to_string(group) : type_name(t);
  g.to_memory = interconnect_->l2_port(m.first_source + group * lc.l2.banks, owner + ".l2");
  g.l2 = std::make_unique<Cache>("l2", lc.l2, clock_, g.to_memory.get());
  g.to_memory->set_requester(g.l2.get());
  g.icnt = std::make_unique<Crossbar>("icnt", lc.link, clock_, l1_sources, lc.l2.banks);
  m.l2s.push_back(g.l2.get());
  m.icnts.push_back(g.icnt.get());
  return g;
}

std::unique_ptr<UnitMemory> MemorySystem::build_unit(Type t, uint32_t index,
                                                     const FillListener* requester) {
  TypeMemory& m = types_[t];
  auto u = std::make_unique<UnitMemory>();
  // The L2 this L1 reaches, and its source port on that L2's crossbar.
  L2Group* g = nullptr;
  uint32_t source = index;
  if (m.private_l2) {
    u->private_l2 = build_group(t, index, 1);
    g = &u->private_l2;
    source = 0;
  } else if (m.shared) {
    g = &m.shared->group;
  } else if (t == kCulling && types_[kShading].shared) {  // after the shading units' ports
    g = &types_[kShading].shared->group;
    source = cfg_.shading.count;
  } else {  // shading (and culling) on the IST's shared L2, after the IST units' ports
    g = &types_[kIst].shared->group;
    source = cfg_.ist.count + (t == kCulling ? cfg_.shading.count : index);
  }
  u->port = std::make_unique<CrossbarPort>(g->icnt.get(), source, nullptr, g->l2.get(),
                                           g->l2->config().line_bytes);
  g->l2->name_requester(u->port.get(), type_name(t));
  u->l1 = std::make_unique<Cache>("l1", m.cfg->l1, clock_, u->port.get());
  u->l1->name_requester(requester, type_name(t));
  if (m.l1s.size() <= index) m.l1s.resize(index + 1, nullptr);
  m.l1s[index] = u->l1.get();
  return u;
}

void MemorySystem::register_stats(StatsRegistry& r, const sc_core::sc_object& top,
                                  const Tick* end) const {
  // Totals over a set of caches, beside the per-instance figures.
  auto totals = [&r](const std::string& prefix, std::vector<const Cache*> caches) {
    auto sum = [caches](uint64_t CacheStats::*field) {
      return [caches, field] {
        uint64_t n = 0;
        for (const Cache* c : caches) n += c->stats().*field;
        return double(n);
      };
    };
    for (auto [name, field] :
         {std::pair{"accesses", &CacheStats::accesses}, std::pair{"hits", &CacheStats::hits},
          std::pair{"misses", &CacheStats::misses},
          std::pair{"mshr_merges", &CacheStats::mshr_merges}})
      r.formula(prefix + "." + name, sum(field), "count", "all of " + prefix + ": " + name);
    r.formula(
        prefix + ".hit_rate",
        [h = sum(&CacheStats::hits), a = sum(&CacheStats::accesses)] {
          return a() > 0 ? h() / a() : 0.0;
        },
        "ratio", "all of " + prefix + ": hits / accesses");
  };
  for (int t = 0; t < kTypes; ++t) {
    const TypeMemory& m = types_[t];
    const std::string type = type_name(Type(t));
    for (const Cache* c : m.l1s) c->register_stats(r, stat_prefix(*c, top));
    // (The culling unit's one L1 is culling.l1 itself.)
    if (!m.l1s.empty() && t != kCulling)
      totals(type + ".l1", std::vector<const Cache*>(m.l1s.begin(), m.l1s.end()));
    for (const Cache* c : m.l2s) c->register_stats(r, stat_prefix(*c, top));
    for (const Crossbar* x : m.icnts) x->register_stats(r, stat_prefix(*x, top), end);
    if (m.private_l2) totals(type + ".l2", std::vector<const Cache*>(m.l2s.begin(), m.l2s.end()));
  }
  interconnect_->register_stats(r, "memory", end);
}

void MemorySystem::invalidate() {
  for (TypeMemory& m : types_) {
    for (Cache* c : m.l1s)
      if (c) c->invalidate();
    for (Cache* c : m.l2s) c->invalidate();
  }
}

}  // namespace rtsim::model
