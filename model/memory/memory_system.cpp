#include "model/memory/memory_system.h"

#include "model/sim/report.h"

namespace rtsim::model {

// A shared L2, named after its group: its children are `l2` and `icnt`, and its clients' ports.
class MemorySystem::SharedL2 : public sc_core::sc_module {
 public:
  SharedL2(sc_core::sc_module_name name, const L2Config& cfg, std::unique_ptr<CrossbarPort> below,
           const Clock& clock)
      : sc_core::sc_module(name),
        to_memory(std::move(below)),
        l2("l2", cfg.l2, clock, to_memory.get()),
        icnt("icnt", cfg.link, clock, uint32_t(cfg.clients.size()), cfg.l2.banks) {
    for (uint32_t s = 0; s < cfg.clients.size(); ++s) {
      ports.push_back(std::make_unique<CrossbarPort>(&icnt, s, 1, &l2, cfg.l2.line_bytes));
      l2.name_requester(ports.back().get(), cfg.clients[s]);
    }
  }
  std::unique_ptr<CrossbarPort> to_memory;
  Cache l2;
  Crossbar icnt;
  std::vector<std::unique_ptr<CrossbarPort>> ports;  // by source
};

MemorySystem::MemorySystem(const MemorySystemConfig& config, const Clock& clock,
                           Calendar& calendar) {
  uint32_t banks = 0;
  for (const L2Config& l2 : config.l2s) banks += l2.l2.banks;
  interconnect_ = std::make_unique<MemoryInterconnect>(
      "memory", config.memory_link, config.dram, clock, calendar, banks, config.writers,
      config.reader, config.write_buffer, config.memory_target);
  uint32_t first = 0;
  for (const L2Config& l2 : config.l2s) {
    auto port = interconnect_->l2_port(first, l2.l2.banks, l2.name + ".l2");
    first += l2.l2.banks;
    if (l2.clients.empty()) {
      shared_.push_back(nullptr);
      to_memory_.push_back(std::move(port));
    } else {
      shared_.push_back(std::make_unique<SharedL2>(l2.name.c_str(), l2, std::move(port), clock));
      to_memory_.push_back(nullptr);
    }
  }
}

MemorySystem::~MemorySystem() = default;

LineSource& MemorySystem::client_port(size_t l2, uint32_t source) {
  if (l2 >= shared_.size() || !shared_[l2] || source >= shared_[l2]->ports.size())
    report_error(kReportInternal, "memory: no source " + std::to_string(source) +
                                      " on a shared L2 numbered " + std::to_string(l2));
  return *shared_[l2]->ports[source];
}

LineSource& MemorySystem::memory_port(size_t l2) {
  if (l2 >= to_memory_.size() || !to_memory_[l2])
    report_error(kReportInternal, "memory: no private L2 numbered " + std::to_string(l2));
  return *to_memory_[l2];
}

void MemorySystem::register_stats(StatsRegistry& r, const sc_core::sc_object& top,
                                  const Tick* span) const {
  for (const auto& g : shared_) {
    if (!g) continue;
    g->l2.register_stats(r, stat_prefix(g->l2, top));
    g->icnt.register_stats(r, stat_prefix(g->icnt, top), span);
  }
  interconnect_->register_stats(r, "memory", span);
}

Cache* MemorySystem::shared_l2(size_t l2) const {
  return l2 < shared_.size() && shared_[l2] ? &shared_[l2]->l2 : nullptr;
}

std::vector<const Cache*> MemorySystem::shared_l2s() const {
  std::vector<const Cache*> l2s;
  for (const auto& g : shared_)
    if (g) l2s.push_back(&g->l2);
  return l2s;
}

void MemorySystem::invalidate() {
  for (auto& g : shared_)
    if (g) g->l2.invalidate();
}

}  // namespace rtsim::model
