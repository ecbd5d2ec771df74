// A memory client's own caches (a unit's): its L1 and, when its L2 is private, that L2 and the
// crossbar from the L1 to its banks, built as children of the module under construction (`l1`,
// and `l2` and `icnt`), with the port below them (`mem_side`, a child of that module too). The
// last cache reaches what the port is bound to (a shared L2's crossbar port, or the memory
// crossbar, model/memory/memory_system.h) once the owner connects it at the end of elaboration.
// Who shares which level is the netlist's data; nothing here names a client. A unit holds its
// ClientCaches on the heap: the port and the caches' owners are cold, and would otherwise sit
// among what every activation reads.
#pragma once

#include "model/memory/cache.h"
#include "model/memory/crossbar.h"
#include "model/sim/stats_registry.h"

#include <systemc>

#include <memory>
#include <string>
#include <vector>

namespace rtsim::model {

// One L2 shared by all clients of a type, or a private L2 per client.
enum class L2Sharing { kType, kUnit };

// A client type's caches: an L1 per client and the L2 level behind them.
struct TypeMemoryConfig {
  uint32_t count = 1;  // clients of the type (one L1 each)
  CacheConfig l1, l2;
  LinkConfig link;  // the crossbar between the type's L1s and its L2
  L2Sharing l2_sharing = L2Sharing::kType;
};

class ClientCaches {
 public:
  sc_core::sc_port<LineSource> mem_side;  // below the last cache: a shared L2's port, or memory

  // `requester` (the client) is named `type` in the L1's bank statistics, and the L1 in a private
  // L2's. `private_l2`: build cfg.l2 behind cfg.link as the client's own.
  ClientCaches(const TypeMemoryConfig& cfg, bool private_l2, const Clock& clock,
               const FillListener* requester, const std::string& type);
  ClientCaches(const ClientCaches&) = delete;
  ClientCaches& operator=(const ClientCaches&) = delete;
  ~ClientCaches();

  Cache& l1() const { return *l1_; }
  Cache* l2() const { return l2_.get(); }  // the private L2, or null
  // Connects the last cache to what mem_side is bound to (at the end of elaboration, before
  // the first access).
  void connect_below();
  void invalidate();
  // Every cache and crossbar under its name relative to `top`; `span`: the window of
  // utilisations.
  void register_stats(StatsRegistry& r, const sc_core::sc_object& top, const Tick* span) const;

 private:
  std::unique_ptr<Cache> l2_;
  std::unique_ptr<Crossbar> icnt_;
  std::unique_ptr<CrossbarPort> to_l2_;
  std::unique_ptr<Cache> l1_;
};

// <prefix>.{accesses,hits,misses,mshr_merges,hit_rate} over `caches` (a type's L1s, or its
// private L2s), beside each cache's own figures.
void register_cache_totals(StatsRegistry& r, const std::string& prefix,
                           std::vector<const Cache*> caches);

}  // namespace rtsim::model
