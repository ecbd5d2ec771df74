// The accelerator's memory hierarchy, built from one AcceleratorConfig: an L1 per unit; per unit
// type one L2 shared by its units (`l2.sharing: type`, our reading of the paper's Table 2) or one
// private L2 per unit (`unit`, the reading of its Section 4.1: "each unit includes L1 and L2
// caches"); a crossbar between each L2 and the L1s it serves (the shading L1 shares the IST's L2,
// or has its own with the IST's L2 configuration when those are private); and one crossbar between
// every L2 bank and the DRAM channels.
//
// Statistics: <type>.l1.unit<i>.* and <type>.l1.* totals; a shared L2 as <type>.l2.* with its
// crossbar <type>.icnt.*; private L2s as <type>.l2.unit<i>.* (and <type>.icnt.unit<i>.*) with
// totals <type>.l2.{accesses,hits,misses,mshr_merges,hit_rate}; memory.icnt.*.
#pragma once

#include "model/cache.h"
#include "model/crossbar.h"
#include "model/stats_registry.h"

#include <array>
#include <memory>
#include <string>
#include <vector>

namespace rtsim::model {

struct AcceleratorConfig;

class MemorySystem {
 public:
  enum Type { kTrv, kList, kIst, kShading, kTypes };

  // `memory` is the DRAM (or any LineSource with ports); it must outlive this.
  MemorySystem(const AcceleratorConfig& cfg, LineSource* memory, const Clock& clock);
  MemorySystem(const MemorySystem&) = delete;
  MemorySystem& operator=(const MemorySystem&) = delete;

  Cache& l1(Type t, uint32_t unit) { return *types_[t].l1s[unit]; }
  const std::vector<std::unique_ptr<Cache>>& l1s(Type t) const { return types_[t].l1s; }
  // Registers every cache and crossbar; `end` is the frame's end time (utilisations).
  void register_stats(StatsRegistry& r, const Tick* end) const;

 private:
  struct Group {  // one L2 and what connects it
    std::unique_ptr<CrossbarPort> to_memory;
    std::unique_ptr<Cache> l2;
    std::unique_ptr<Crossbar> icnt;
  };
  struct TypeMemory {
    std::string name;
    std::vector<Group> groups;                         // one (shared) or one per unit (private)
    std::vector<std::unique_ptr<CrossbarPort>> ports;  // each L1's way to its L2
    std::vector<std::unique_ptr<Cache>> l1s;
  };

  std::unique_ptr<Crossbar> memory_icnt_;
  std::array<TypeMemory, kTypes> types_;
};

}  // namespace rtsim::model
