// IST: one ray-triangle test per operation (36-cycle pipeline): the 48-byte triangle record is
// fetched through the unit's L1 (two lines when it straddles) and tested with the watertight test
// on the leaf's acceptance window. Closest-hit updates go through the LVB updater. After a leaf's
// last test the ray goes back to its TRV unit, or to shading when its traversal is over.
#pragma once

#include "model/memory/cache.h"
#include "model/units/lvb_updater.h"
#include "model/units/ray_owners.h"
#include "model/units/ray_unit.h"

#include <vector>

namespace rtsim::model {

struct IstStats {
  uint64_t tests = 0;
  uint64_t hits = 0;
};

class IstUnit : public RayUnit {
 public:
  // Unit `index` of the IST units; rays go back through `owners`, closest hits through `lvb`.
  IstUnit(sc_core::sc_module_name name, const ModelContext& ctx, const RayUnitConfig& cfg,
          MemorySystem& memory, uint32_t index, RayOwners* owners, LvbUpdater* lvb);
  const IstStats& stats() const { return stats_; }
  void register_stats(StatsRegistry& r, const std::string& prefix) const;

 protected:
  void process(uint32_t ray, Tick now) override;

 private:
  uint32_t latency_;
  RayOwners* owners_;
  LvbUpdater* lvb_;
  IstStats stats_;
};

}  // namespace rtsim::model
