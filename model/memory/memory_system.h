// The accelerator's memory hierarchy below its clients' own caches, built from data: the L2s on
// the memory crossbar (each shared by the clients it lists, or one client's private L2), and the
// memory interconnect behind them (one crossbar from every L2 bank, the frame-buffer writers and
// the record reader to the memory channels, model/memory/memory_interconnect.h). Nothing here
// names a unit: the netlist says which clients share which L2 (model/accelerator_topology.cpp).
//
// A shared L2 and its crossbar are `<name>.l2` and `<name>.icnt`, children of a module `<name>`
// built in the current scope; a client reaches it through client_port(l2, source), its source on
// that crossbar. A private L2 is its client's own child (model/memory/client_caches.h); here it
// has only its way to memory, memory_port(l2). The memory crossbar is `memory.icnt`, the TLM-2.0
// port `memory.port`.
#pragma once

#include "model/memory/cache.h"
#include "model/memory/crossbar.h"
#include "model/memory/memory_interconnect.h"
#include "model/sim/stats_registry.h"

#include <systemc>

#include <memory>
#include <string>
#include <vector>

namespace rtsim::model {

// One L2 on the memory crossbar: shared (built here) or a client's private one (built by it).
struct L2Config {
  // Shared: the module holding `l2` and `icnt`; private: its client. The memory trace names the
  // L2 `<name>.l2`.
  std::string name;
  CacheConfig l2;
  LinkConfig link;  // shared: the crossbar from its clients' L1s to its banks
  // Shared: its crossbar's sources in order, each named by its client's type (the L2's bank
  // statistics by requester); empty: a private L2.
  std::vector<std::string> clients;
};

struct MemorySystemConfig {
  std::vector<L2Config> l2s;         // in the memory crossbar's source order, one source per bank
  LinkConfig memory_link;            // the crossbar between the L2 banks and the memory channels
  std::vector<std::string> writers;  // the frame-buffer writers, named as in the memory trace
  std::string reader = "reader";     // the record reader, likewise
  uint32_t write_buffer = 0;         // a writer's posted writes in flight (0: unbounded)
  DramConfig dram;  // the memory's address mapping (the channels) and its request size
  PortTarget memory_target = PortTarget::kPlatform;  // what the memory port is bound to
};

class MemorySystem {
 public:
  // Builds, in the current module's scope, the memory interconnect (`memory`, whose port speaks
  // TLM-2.0 to a memory with the configuration `dram`) and a module per shared L2.
  MemorySystem(const MemorySystemConfig& cfg, const Clock& clock, Calendar& calendar);
  MemorySystem(const MemorySystem&) = delete;
  MemorySystem& operator=(const MemorySystem&) = delete;
  ~MemorySystem();

  // Source `source` of shared L2 `l2`'s crossbar: a client L1's way to that L2.
  LineSource& client_port(size_t l2, uint32_t source);
  // Private L2 `l2`'s way to memory.
  LineSource& memory_port(size_t l2);

  MemoryInterconnect& interconnect() { return *interconnect_; }
  // The shared L2s, in the configuration's order.
  std::vector<const Cache*> shared_l2s() const;
  // Shared L2 `l2` (null when it is a client's private one): functional warming reaches it.
  Cache* shared_l2(size_t l2) const;
  // Empties the shared L2s (Cache::invalidate); the clients empty their own caches.
  void invalidate();
  // Registers every shared L2 and crossbar and the interconnect under its name relative to `top`;
  // `span`: the statistics' time span (utilisations).
  void register_stats(StatsRegistry& r, const sc_core::sc_object& top, const Tick* span) const;

 private:
  class SharedL2;  // the sc_module `<name>` holding a shared L2 and its crossbar
  std::unique_ptr<MemoryInterconnect> interconnect_;
  std::vector<std::unique_ptr<SharedL2>> shared_;         // by L2, null for a private one
  std::vector<std::unique_ptr<CrossbarPort>> to_memory_;  // by L2: private ones only
};

}  // namespace rtsim::model
