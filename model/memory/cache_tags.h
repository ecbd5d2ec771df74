// A cache's tags and LRU order without time (no MSHRs, no banks, no data): the state the
// accelerator's functional mode keeps of each of its caches (model/functional/). Sets are indexed
// by the line number's low bits and a miss takes its set's LRU way, as Cache does
// (model/memory/cache.h), so a stream of lines hits and misses in it as it would in a Cache whose
// requests never overlap. Line numbers of 32-bit addresses fit in 32 bits: a way is 4 bytes (a
// Cache's 32), and a functional pass's tag arrays stay in the host's nearer caches.
#pragma once

#include "model/memory/cache.h"

#include <cstdint>
#include <vector>

namespace rtsim::model {

class CacheTags {
 public:
  // A cache of `cfg`'s geometry (size, ways, line size), which must be valid
  // (CacheConfig::validate).
  explicit CacheTags(const CacheConfig& cfg)
      : ways_(cfg.ways), set_mask_(cfg.sets() - 1), tags_(size_t(cfg.sets()) * cfg.ways, kEmpty) {}
  // Looks up line number `line64` (address / line bytes); a miss puts it in its set's LRU way.
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

 private:
  static constexpr uint32_t kEmpty = ~uint32_t(0);
  uint32_t ways_;
  uint32_t set_mask_;
  std::vector<uint32_t> tags_;  // set x ways + way, each set from its MRU way to its LRU way
};

}  // namespace rtsim::model
