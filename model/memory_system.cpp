#include "model/memory_system.h"

#include "model/accelerator.h"

namespace rtsim::model {

MemorySystem::MemorySystem(const AcceleratorConfig& cfg, Dram* dram, const Clock& clock) : dram_(dram) {
  LineSource* memory = dram;
  const UnitTypeConfig* unit_cfg[kTypes] = {&cfg.trv, &cfg.list, &cfg.ist, &cfg.shading};
  const char* names[kTypes] = {"trv", "list", "ist", "shading"};
  const bool ist_private = cfg.ist.l2_sharing == L2Sharing::kUnit;
  // The L2 configuration and the number of L2s of each type (the shading unit has its own L2 only
  // when the IST's are private; otherwise its L1 is one more source on the IST's crossbar).
  auto l2_cfg = [&](int t) -> const UnitTypeConfig& { return t == kShading ? cfg.ist : *unit_cfg[t]; };
  auto l2_count = [&](int t) -> uint32_t {
    if (t == kShading) return ist_private ? 1 : 0;
    return unit_cfg[t]->l2_sharing == L2Sharing::kUnit ? unit_cfg[t]->count : 1;
  };
  uint32_t sources = 0;
  for (int t = 0; t < kTypes; ++t) sources += l2_count(t) * l2_cfg(t).l2.banks;
  first_writer_ = sources;
  sources += cfg.shading.count + 1;
  memory_icnt_ = std::make_unique<Crossbar>("memory.icnt", cfg.memory_link, clock, sources, memory->port_count());
  record_reader_ = std::make_unique<CrossbarPort>(memory_icnt_.get(), sources - 1, nullptr, memory, dram->engine().config().request_bytes);

  uint32_t first_source = 0;
  for (int t = 0; t < kTypes; ++t) {
    TypeMemory& m = types_[t];
    m.name = names[t];
    const UnitTypeConfig& u = *unit_cfg[t];
    const UnitTypeConfig& lc = l2_cfg(t);
    const uint32_t groups = l2_count(t);
    for (uint32_t g = 0; g < groups; ++g) {
      Group grp;
      const std::string suffix = groups > 1 ? ".unit" + std::to_string(g) : "";
      grp.to_memory = std::make_unique<CrossbarPort>(memory_icnt_.get(), first_source, nullptr, memory, lc.l2.line_bytes);
      first_source += lc.l2.banks;
      grp.l2 = std::make_unique<Cache>(m.name + ".l2" + suffix, lc.l2, clock, grp.to_memory.get());
      grp.to_memory->set_requester(grp.l2.get());
      const uint32_t l1s = groups > 1 ? 1 : u.count + (t == kIst && !ist_private ? cfg.shading.count : 0);
      grp.icnt = std::make_unique<Crossbar>(m.name + ".icnt" + suffix, lc.link, clock, l1s, lc.l2.banks);
      m.groups.push_back(std::move(grp));
    }
  }
  // Each L1's port on its L2's crossbar, then the L1 itself.
  for (int t = 0; t < kTypes; ++t) {
    TypeMemory& m = types_[t];
    const UnitTypeConfig& u = *unit_cfg[t];
    for (uint32_t i = 0; i < u.count; ++i) {
      const bool shared_ist = t == kShading && !ist_private;
      Group& g = shared_ist ? types_[kIst].groups[0] : m.groups[m.groups.size() > 1 ? i : 0];
      const uint32_t source = shared_ist ? cfg.ist.count + i : (m.groups.size() > 1 ? 0 : i);
      m.ports.push_back(std::make_unique<CrossbarPort>(g.icnt.get(), source, nullptr, g.l2.get(), g.l2->config().line_bytes));
      g.l2->name_requester(m.ports.back().get(), m.name);
      m.l1s.push_back(std::make_unique<Cache>(m.name + std::to_string(i) + ".l1", u.l1, clock, m.ports.back().get()));
    }
  }
}

void MemorySystem::write_line(uint32_t writer, uint64_t line, const uint8_t* data, Tick now) {
  const uint32_t bytes = dram_->engine().config().request_bytes;
  const Tick arrived = memory_icnt_->request(first_writer_ + writer, dram_->port_of(line), bytes, now);
  dram_->write_line(line, data, arrived);
}

void MemorySystem::register_stats(StatsRegistry& r, const Tick* end) const {
  // Totals over a set of caches, beside the per-instance figures.
  auto totals = [&r](const std::string& prefix, std::vector<const Cache*> caches) {
    auto sum = [caches](uint64_t CacheStats::*field) {
      return [caches, field] {
        uint64_t n = 0;
        for (const Cache* c : caches) n += c->stats().*field;
        return double(n);
      };
    };
    for (auto [name, field] : {std::pair{"accesses", &CacheStats::accesses}, std::pair{"hits", &CacheStats::hits},
                               std::pair{"misses", &CacheStats::misses}, std::pair{"mshr_merges", &CacheStats::mshr_merges}})
      r.formula(prefix + "." + name, sum(field), "all of " + prefix + ": " + name);
    r.formula(prefix + ".hit_rate", [h = sum(&CacheStats::hits), a = sum(&CacheStats::accesses)] {
      return a() > 0 ? h() / a() : 0.0;
    }, "all of " + prefix + ": hits / accesses");
  };
  for (const TypeMemory& m : types_) {
    std::vector<const Cache*> l1s;
    for (size_t i = 0; i < m.l1s.size(); ++i) {
      m.l1s[i]->register_stats(r, m.name + ".l1.unit" + std::to_string(i));
      l1s.push_back(m.l1s[i].get());
    }
    if (!l1s.empty()) totals(m.name + ".l1", l1s);
    if (m.groups.size() == 1) {
      m.groups[0].l2->register_stats(r, m.name + ".l2");
      m.groups[0].icnt->register_stats(r, m.name + ".icnt", end);
      continue;
    }
    std::vector<const Cache*> l2s;
    for (size_t g = 0; g < m.groups.size(); ++g) {
      m.groups[g].l2->register_stats(r, m.name + ".l2.unit" + std::to_string(g));
      m.groups[g].icnt->register_stats(r, m.name + ".icnt.unit" + std::to_string(g), end);
      l2s.push_back(m.groups[g].l2.get());
    }
    if (!l2s.empty()) totals(m.name + ".l2", l2s);
  }
  memory_icnt_->register_stats(r, "memory.icnt", end);
}

}  // namespace rtsim::model
