// IST: one ray-triangle test per operation (36-cycle pipeline): the 48-byte triangle record is
// fetched through the unit's L1 (two lines when it straddles) and tested with the watertight test
// on the leaf's acceptance window. Closest-hit updates go through the LVB updater. When a leaf's
// last test completes the ray goes back to its TRV unit, which pops its stack; if its traversal
// is over it goes to shading instead.
//
// Ports: `back` (RayReturn: to the ray's TRV unit), `to_shading`, `lvb` (the LVB updater).
#pragma once

#include "model/sim/stats_description.h"

#include "model/memory/cache.h"
#include "model/units/ray_ports.h"
#include "model/units/ray_unit.h"

namespace rtsim::model {

struct IstStats {
  uint64_t tests = 0;
  uint64_t hits = 0;
};

// Every IstStats field, once (model/sim/stats_description.h).
template <class V>
void describe_stats(V& v, const IstStats& s) {
  v.counter("tests", s.tests, "count", "ray-triangle tests");
  v.counter("hits", s.hits, "count", "tests that hit inside the leaf's window");
}

class IstUnit : public RayUnit {
 public:
  sc_core::sc_port<RayReturn> back;
  RayOut to_shading;
  sc_core::sc_port<LvbUpdate> lvb;

  IstUnit(sc_core::sc_module_name name, const ModelContext& ctx, const UnitTypeConfig& cfg);
  const IstStats& stats() const { return stats_; }
  void register_stats(StatsRegistry& r, const std::string& prefix) const override;

 protected:
  void process(uint32_t ray, Tick now) override;
  void admitted(uint32_t ray) override;

 private:
  uint32_t latency_;
  IstStats stats_;
};

}  // namespace rtsim::model
