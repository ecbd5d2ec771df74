// The accelerator's memory hierarchy, built from one AcceleratorConfig: an L1 per unit; per unit
// type one L2 shared by its units (`l2.sharing: type`, our reading of the paper's Table 2) or one
// private L2 per unit (`unit`, the reading of its Section 4.1: "each unit includes L1 and L2
// caches"); a crossbar between each L2 and the L1s it serves (the shading L1 shares the IST's L2,
// or has its own with the IST's L2 configuration when those are private); and one crossbar between
// every L2 bank and the DRAM channels, on which the shading units also write the frame buffer
// and the shadow culling unit reads it back (model/hit_record.h).
//
// Statistics: <type>.l1.unit<i>.* and <type>.l1.* totals; a shared L2 as <type>.l2.* with its
// crossbar <type>.icnt.*; private L2s as <type>.l2.unit<i>.* (and <type>.icnt.unit<i>.*) with
// totals <type>.l2.{accesses,hits,misses,mshr_merges,hit_rate}; memory.icnt.*.
#pragma once

#include "model/cache.h"
#include "model/crossbar.h"
#include "model/dram.h"
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

  // `dram` must outlive this.
  MemorySystem(const AcceleratorConfig& cfg, Dram* dram, const Clock& clock);
  MemorySystem(const MemorySystem&) = delete;
  MemorySystem& operator=(const MemorySystem&) = delete;

  Cache& l1(Type t, uint32_t unit) { return *types_[t].l1s[unit]; }
  const std::vector<std::unique_ptr<Cache>>& l1s(Type t) const { return types_[t].l1s; }
  // A posted write of a whole line by shading unit `writer`: it crosses the memory crossbar from
  // the writer's port, then queues in the DRAM; the bytes are stored at once.
  void write_line(uint32_t writer, uint64_t line, const uint8_t* data, Tick now);
  // The shadow culling unit's way to read the frame buffer (no cache: records are streamed).
  CrossbarPort& record_reader() { return *record_reader_; }
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

  Dram* dram_;
  std::unique_ptr<Crossbar> memory_icnt_;
  uint32_t first_writer_ = 0;  // memory crossbar sources: L2 banks, then writers, then the reader
  std::unique_ptr<CrossbarPort> record_reader_;
  std::array<TypeMemory, kTypes> types_;
};

}  // namespace rtsim::model
