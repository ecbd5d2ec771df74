// The accelerator in functional mode (a sampled frame's functional pass, docs/sampling.md): its
// caches as tags (model/memory/cache_tags.h), the ray path and the latencies the pass's rough clock
// uses, all built from the unit table and the memory topology the netlist is built from
// (model/accelerator_units.h, model/accelerator_topology.h): an L1 per unit, the L2 each unit's
// caches reach (a type's shared one, a private one per unit, or the one its row names: the shading
// L1s on the IST's), and the culling unit's L1 for the lights (shading unit 0's, or its own beside
// the shading L1s). A unit's L1 miss goes to its L2, an L2 miss is a line read from DRAM. No time,
// no MSHRs, no banks: a line is in a cache from the access that misses on it (a request the model
// would merge into an MSHR in flight is a hit here). A line read from DRAM finds its bank's row as
// the configured DRAM leaves it (model/memory/dram_rows.h).
#pragma once

#include "kernels/access_stream.h"
#include "model/accelerator_config.h"
#include "model/memory/cache_tags.h"
#include "model/memory/dram_rows.h"
#include "model/units/ray_state.h"

#include <array>
#include <cstdint>
#include <vector>

namespace rtsim::model {

// What a stream of reads did to the caches, by the stage whose unit read (stage_of).
struct CacheCounts {
  std::array<uint64_t, kStages> reads{};      // records read
  std::array<uint64_t, kStages> l1_lines{};   // L1 lookups: the lines covering each record
  std::array<uint64_t, kStages> l1_misses{};  // ... that missed (L2 lookups)
  std::array<uint64_t, kStages> l2_misses{};  // ... that missed there too: DRAM line reads
  void add(const CacheCounts& o);
};

// A line a read missed in its L1: the L2 it went to (an index of the machine's L2s) and whether it
// missed there too (a line read from DRAM).
struct LineMiss {
  uint32_t line = 0;  // address / line bytes
  uint32_t l2 = 0;
  bool dram = false;
};

// A stage's latencies in the accelerator's cycles, from the hardware file: its pipeline, its L1's
// hit, and of the L2 its L1s miss to, the link's latency, the L2's hit latency, and the cycles a
// line takes a port of the link back (its flits).
struct StageTiming {
  uint32_t latency = 0, l1_hit = 0, link_latency = 0, l2_latency = 0, reply_flits = 0;
  uint32_t l2_hit = 0;       // an L1 miss's L2 hit: the link both ways, the flits, the L2's hit
  bool shared_fill = false;  // a line filled into the L1 takes a cycle of its port (fill_port)
};

class FunctionalMachine {
 public:
  explicit FunctionalMachine(const AcceleratorConfig& cfg);

  // The record `a`, read for a ray of traversal unit `t` by the unit of its stage on that ray's
  // path (a light record: by the culling unit): each line covering it goes through that unit's L1,
  // and its L2 on a miss. Returns the deepest level a line of it came from: 0 the L1, 1 the L2,
  // 2 DRAM. With `misses`, each line that missed the L1 is appended to it.
  int read(uint32_t t, const Access& a, CacheCounts& counts,
           std::vector<LineMiss>* misses = nullptr);

  // The unit of stage `s` a ray of traversal unit `t` visits (model::ray_route).
  uint32_t unit(Stage s, uint32_t t) const { return routes_[t][s]; }
  uint32_t units(Stage s) const { return uint32_t(l1_[s].size()); }
  const StageTiming& timing(Stage s) const { return timing_[s]; }
  // The cycles of a read by stage `s` whose deepest line came from `level` (read()), queues aside,
  // `addr` the line read from DRAM (level 2).
  uint64_t read_cycles(Stage s, int level, uint64_t addr) {
    const StageTiming& t = timing_[s];
    return t.l1_hit + (level >= 1 ? t.l2_hit : 0) + (level >= 2 ? dram_cycles(addr) : 0);
  }
  // The line at `addr` read from DRAM: the memory link both ways, its flits, and the DRAM's access
  // from the state its bank's row is in (DramRows), which the read leaves as the DRAM would.
  uint32_t dram_cycles(uint64_t addr) { return dram_[rows_.read(addr)]; }
  uint32_t line_flits() const { return line_flits_; }  // cycles a line takes a memory-link port
  // The shading unit's issue interval: the larger of its two reads and its hit record's write over
  // the memory link.
  uint32_t shading_interval() const { return shading_interval_; }
  uint32_t line_bytes() const { return line_bytes_; }
  uint32_t line_shift() const { return line_shift_; }  // log2 of line_bytes()
  uint32_t l2_count() const { return uint32_t(l2s_.size()); }
  uint32_t l2_banks(uint32_t l2) const { return l2_banks_[l2]; }

 private:
  std::array<std::vector<CacheTags>, kStages> l1_;
  std::array<std::vector<uint32_t>, kStages> l2_of_;  // each unit's L2, an index of l2s_
  std::vector<CacheTags> l2s_;
  std::vector<uint32_t> l2_banks_;
  std::vector<CacheTags> culling_l1_;  // the culling unit's own L1 (culling.l1: own), if any
  uint32_t culling_l2_ = 0;
  std::vector<std::array<uint32_t, kStages>> routes_;  // by traversal unit
  std::array<StageTiming, kStages> timing_{};
  DramRows rows_;
  uint32_t dram_[DramRows::kOutcomes] = {};  // by what the bank found
  uint32_t line_flits_ = 1, shading_interval_ = 2;
  uint32_t line_bytes_ = 64, line_shift_ = 6;
};

}  // namespace rtsim::model
