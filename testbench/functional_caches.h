// The accelerator's caches as tags alone (issue 38, docs/sampling.md): what a sampled frame's
// functional pass keeps of them. No time, no MSHRs, no banks: a line is in a cache from the access
// that misses on it (a request the model would merge into an MSHR in flight is a hit here).
//
// The hierarchy is the model's (model/accelerator_topology.cpp): an L1 per unit; per unit type one
// L2 its units share (`l2.sharing: type`) or one L2 per unit (`unit`); the shading units' L1s on
// the IST's L2 (an L2 of their own with the IST's configuration when the IST's are private). A
// unit's L1 miss goes to its L2, an L2 miss is a line read from DRAM.
#pragma once

#include "kernels/access_stream.h"
#include "model/accelerator_config.h"

#include <array>
#include <cstdint>
#include <vector>

namespace rtsim {

// A set-associative cache's tags with LRU replacement; sets are indexed by the line number's low
// bits, as model/memory/cache.h does. Line numbers of 32-bit addresses fit in 32 bits: the tags
// are half the size, and the pass's tag arrays stay in the host's nearer caches.
class TagArray {
 public:
  TagArray(uint32_t size_bytes, uint32_t ways, uint32_t line_bytes);
  // Looks up line number `line` (address / line bytes); a miss puts it in its set's LRU way.
  // True on a hit.
  bool access(uint64_t line64) {
    const uint32_t line = uint32_t(line64);
    uint32_t* set = &tags_[(line & set_mask_) * ways_];
    if (set[0] == line) return true;  // the MRU way: most hits
    uint32_t w = 1;
    while (w < ways_ && set[w] != line) ++w;
    const bool hit = w < ways_;
    if (!hit) w = ways_ - 1;  // the LRU way goes
    for (; w > 0; --w) set[w] = set[w - 1];
    set[0] = line;
    return hit;
  }
  uint32_t sets() const { return uint32_t(set_mask_ + 1); }
  uint32_t ways() const { return ways_; }

 private:
  static constexpr uint32_t kEmpty = ~uint32_t(0);
  uint32_t ways_;
  uint32_t set_mask_;
  std::vector<uint32_t> tags_;  // set x ways + way, each set from its MRU way to its LRU way
};

// What a stream of reads did to the caches, by the type of unit that read.
struct CacheCounts {
  std::array<uint64_t, kAccessUnits> reads{};      // records read
  std::array<uint64_t, kAccessUnits> l1_lines{};   // L1 lookups: the lines covering each record
  std::array<uint64_t, kAccessUnits> l1_misses{};  // ... that missed (L2 lookups)
  std::array<uint64_t, kAccessUnits> l2_misses{};  // ... that missed there too: DRAM line reads
  void add(const CacheCounts& o);
};

// A line a read missed in its L1: the L2 it went to (an index of the L2s) and whether it missed
// there too (a line read from DRAM).
struct LineMiss {
  uint32_t line = 0;  // address / line bytes
  uint32_t l2 = 0;
  bool dram = false;
};

class FunctionalCaches {
 public:
  // The caches of the machine `cfg` describes (its traversal units: TRV's or the BVH units').
  explicit FunctionalCaches(const model::AcceleratorConfig& cfg);

  // Unit `unit` of type `a.unit` reads the record `a`: each line covering it goes through that
  // unit's L1, and its L2 on a miss. Returns the deepest level a line of it came from: 0 the L1,
  // 1 the L2, 2 DRAM. With `misses`, each line that missed the L1 is appended to it.
  int read(uint32_t unit, const Access& a, CacheCounts& counts,
           std::vector<LineMiss>* misses = nullptr);

  // The units a ray owned by traversal unit `t` visits, by type: the model's ray path
  // (model::ray_route).
  const std::array<uint32_t, kAccessUnits>& route(uint32_t t) const { return routes_[t]; }
  uint32_t count(AccessUnit type) const { return uint32_t(l1_[size_t(type)].size()); }
  uint32_t line_bytes() const { return line_bytes_; }
  uint32_t line_shift() const { return line_shift_; }  // log2 of line_bytes()
  uint32_t l2_count() const { return uint32_t(l2s_.size()); }
  // The unit type whose configuration L2 `l2` has (the shading units' L2 is the IST's).
  AccessUnit l2_type(uint32_t l2) const { return l2_type_[l2]; }

 private:
  std::array<std::vector<TagArray>, kAccessUnits> l1_;
  std::array<std::vector<uint32_t>, kAccessUnits> l2_of_;  // each unit's L2, an index of l2s_
  std::vector<TagArray> l2s_;
  std::vector<AccessUnit> l2_type_;                         // by L2
  std::vector<std::array<uint32_t, kAccessUnits>> routes_;  // by traversal unit
  uint32_t line_bytes_ = 64;
  uint32_t line_shift_ = 6;
};

}  // namespace rtsim
