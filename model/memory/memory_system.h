// The accelerator's memory hierarchy, built from one AcceleratorConfig: an L1 per unit; per unit
// type one L2 shared by its units (`l2.sharing: type`, our reading of the paper's Table 2) or one
// private L2 per unit (`unit`, the reading of its Section 4.1: "each unit includes L1 and L2
// caches"); a crossbar between each L2 and the L1s it serves (the shading L1 shares the IST's L2,
// or has its own with the IST's L2 configuration when those are private); and one crossbar between
// every L2 bank and the memory channels, on which the shading units also write the frame buffer
// and the shadow culling unit reads it back (model/units/hit_record.h).
//
// The blocks are sc_objects named where they sit: a shared L2 and its crossbar are `<type>.l2` and
// `<type>.icnt` (children of a module per unit type); a unit's L1 is `<unit>.l1`, and private L2s
// are `<unit>.l2` and `<unit>.icnt`; the memory crossbar is `memory.icnt`. Each unit builds its
// own caches in its constructor (build_unit), so they are its children. Statistics use the same
// names, plus totals per type: <type>.l1.* over the type's L1s and, with private L2s,
// <type>.l2.{accesses,hits,misses,mshr_merges,hit_rate}; memory.icnt.* and memory.port.*.
#pragma once

#include "model/memory/cache.h"
#include "model/memory/crossbar.h"
#include "model/memory/memory_interconnect.h"
#include "model/sim/stats_registry.h"

#include <systemc>

#include <array>
#include <memory>
#include <string>
#include <vector>

namespace rtsim::model {

// One L2 shared by all units of a type, or a private L2 per unit.
enum class L2Sharing { kType, kUnit };

// A unit type's caches: an L1 per unit and the L2 level behind them.
struct TypeMemoryConfig {
  uint32_t count = 1;  // units of the type (one L1 each)
  CacheConfig l1, l2;
  LinkConfig link;  // the crossbar between the type's L1s and its L2 (shading: the IST's)
  L2Sharing l2_sharing = L2Sharing::kType;
};

struct MemorySystemConfig {
  // The shading units' l2 and link are not used: their L1s sit on the IST's L2.
  TypeMemoryConfig trv, list, ist, shading;
  // The shadow culling unit has an L1 of its own, a shading L1 on the shading units' L2.
  bool culling_l1 = false;
  LinkConfig memory_link;     // the crossbar between the L2 banks and the memory channels
  uint32_t write_buffer = 0;  // a shading unit's posted writes in flight (0: unbounded)
  DramConfig dram;            // the memory's address mapping (the channels) and its request size
  bool loosely_timed_memory = false;  // the memory implements b_transport only
};

// An L2 and what connects it: its port on the memory crossbar and the crossbar from its L1s.
struct L2Group {
  std::unique_ptr<CrossbarPort> to_memory;
  std::unique_ptr<Cache> l2;
  std::unique_ptr<Crossbar> icnt;
};

// What a unit owns of the hierarchy: its L1, its port towards the L2, and a private L2.
struct UnitMemory {
  L2Group private_l2;  // empty unless L2s are private
  std::unique_ptr<CrossbarPort> port;
  std::unique_ptr<Cache> l1;
};

class MemorySystem {
 public:
  enum Type { kTrv, kList, kIst, kShading, kCulling, kTypes };
  static const char* type_name(Type t);

  // Builds, in the current module's scope, the memory interconnect (`memory`, whose port speaks
  // TLM-2.0 to a memory with the configuration `dram`) and one module per unit type with a shared
  // L2.
  MemorySystem(const MemorySystemConfig& cfg, const Clock& clock, Calendar& calendar);
  MemorySystem(const MemorySystem&) = delete;
  MemorySystem& operator=(const MemorySystem&) = delete;
  ~MemorySystem();

  // Called from the constructor of unit `index` of type `t`, which owns the result: its L1 (`l1`)
  // and, when the type's L2s are private, `l2` and `icnt`, as children of that unit. (kCulling:
  // the culling unit's own L1, when the configuration has one.)
  std::unique_ptr<UnitMemory> build_unit(Type t, uint32_t index, const FillListener* requester);

  MemoryInterconnect& interconnect() { return *interconnect_; }
  // Empties every cache (Cache::invalidate).
  void invalidate();
  // Registers every cache and crossbar under its name relative to `top`; `end` is the frame's end
  // time (utilisations).
  void register_stats(StatsRegistry& r, const sc_core::sc_object& top, const Tick* end) const;

 private:
  class TypeModule;  // the sc_module `<type>` holding a shared L2 group
  struct TypeMemory {
    const TypeMemoryConfig* cfg = nullptr;     // the type's own configuration (its L1s, counts)
    const TypeMemoryConfig* l2_cfg = nullptr;  // the configuration its L2s use (shading: the IST's)
    bool private_l2 = false;
    uint32_t first_source = 0;           // its first L2 bank on the memory crossbar
    std::unique_ptr<TypeModule> shared;  // null with private L2s (or shading on the IST's L2)
    std::vector<Cache*> l1s;             // owned by the units
    std::vector<Cache*> l2s;             // owned by the units or `shared`
    std::vector<const Crossbar*> icnts;
  };
  L2Group build_group(Type t, uint32_t group, uint32_t l1_sources);

  MemorySystemConfig cfg_;
  Clock clock_;
  std::unique_ptr<MemoryInterconnect> interconnect_;
  std::array<TypeMemory, kTypes> types_;
};

}  // namespace rtsim::model
