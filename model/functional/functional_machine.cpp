#include "model/functional/functional_machine.h"

#include "model/accelerator_topology.h"
#include "model/accelerator_units.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rtsim::model {

void CacheCounts::add(const CacheCounts& o) {
  for (size_t s = 0; s < kStages; ++s) {
    reads[s] += o.reads[s];
    l1_lines[s] += o.l1_lines[s];
    l1_misses[s] += o.l1_misses[s];
    l2_misses[s] += o.l2_misses[s];
  }
}

namespace {

// Cycles a packet of `bytes` occupies a link.
uint32_t transfer_cycles(const LinkConfig& link, uint32_t bytes) {
  const uint32_t w = link.bytes_per_cycle;
  return w == 0 ? 0 : (bytes + link.header_bytes + w - 1) / w;
}

}  // namespace

FunctionalMachine::FunctionalMachine(const AcceleratorConfig& cfg) : rows_(cfg.memory_dram()) {
  const UnitTypes types = unit_types(cfg);
  const MemoryTopology topology = memory_topology(cfg, MemoryTarget::kBuiltin);
  line_bytes_ = cfg.traversal().l1.line_bytes;
  for (const L2Config& l2 : topology.memory.l2s) {
    l2s_.emplace_back(l2.l2);
    l2_banks_.push_back(l2.l2.banks);
    if (l2.l2.line_bytes != line_bytes_)
      throw std::invalid_argument("the functional pass needs one line size throughout");
  }
  for (size_t s = 0; s < kStages; ++s) {
    const UnitTypeConfig& u = cfg.*types[s]->config;
    if (u.l1.line_bytes != line_bytes_)
      throw std::invalid_argument("the functional pass needs one line size throughout");
    for (uint32_t i = 0; i < u.count; ++i) {
      l1_[s].emplace_back(u.l1);
      l2_of_[s].push_back(uint32_t(topology.units[s][i].l2));
    }
    // The L2 the stage's L1s miss to: the same configuration for each of its units.
    const L2Config& below = topology.memory.l2s[l2_of_[s][0]];
    StageTiming& t = timing_[s];
    t.latency = u.latency;
    t.l1_hit = u.l1.hit_latency;
    t.link_latency = below.link.latency;
    t.l2_latency = below.l2.hit_latency;
    t.reply_flits = transfer_cycles(below.link, line_bytes_);
    t.l2_hit = 2 * t.link_latency + t.reply_flits + t.l2_latency;
    t.shared_fill = u.l1.fill_port == FillPort::kShared;
  }
  if (cfg.culling.l1 == CullingL1::kOwn) {
    culling_l1_.emplace_back(cfg.shading.l1);
    culling_l2_ = uint32_t(topology.culling.l2);
  }
  line_shift_ = 0;
  while ((1u << line_shift_) < line_bytes_) ++line_shift_;
  for (uint32_t t = 0; t < cfg.traversal().count; ++t) routes_.push_back(ray_route(cfg, t));

  const double tck_cycles = double(cfg.memory_dram().tCK_ps) * cfg.clock_ghz / 1000.0;
  line_flits_ = std::max<uint32_t>(1, transfer_cycles(cfg.memory_link, line_bytes_));
  for (int o = 0; o < DramRows::kOutcomes; ++o)
    dram_[o] = 2 * cfg.memory_link.latency + transfer_cycles(cfg.memory_link, line_bytes_) +
               uint32_t(std::lround(rows_.cycles(DramRows::Outcome(o)) * tck_cycles));
  const uint32_t write = cfg.write_records ? transfer_cycles(cfg.memory_link, line_bytes_) : 0;
  shading_interval_ = std::max<uint32_t>(2, write);
}

int FunctionalMachine::read(uint32_t t, const Access& a, CacheCounts& counts,
                            std::vector<LineMiss>* misses) {
  const Stage s = stage_of(a.kind);
  const bool own = a.kind == WalkRead::kLight && !culling_l1_.empty();
  // The culling unit reads the lights through shading unit 0's L1, or its own.
  const uint32_t u = a.kind == WalkRead::kLight ? 0 : routes_[t][s];
  CacheTags& l1 = own ? culling_l1_[0] : l1_[s][u];
  const uint32_t l2_index = own ? culling_l2_ : l2_of_[s][u];
  CacheTags& l2 = l2s_[l2_index];
  ++counts.reads[s];
  int level = 0;
  if (a.bytes == 0) return level;
  const uint64_t first = a.addr >> line_shift_,
                 last = (uint64_t(a.addr) + a.bytes - 1) >> line_shift_;
  for (uint64_t line = first; line <= last; ++line) {
    ++counts.l1_lines[s];
    if (l1.access(line)) continue;
    ++counts.l1_misses[s];
    level = std::max(level, 1);
    const bool l2_hit = l2.access(line);
    if (misses) misses->push_back({uint32_t(line), l2_index, !l2_hit});
    if (l2_hit) continue;
    ++counts.l2_misses[s];
    level = 2;
  }
  return level;
}

}  // namespace rtsim::model
