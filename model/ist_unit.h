// IST: one ray-triangle test per operation (36-cycle pipeline): the 48-byte triangle record is
// fetched through the unit's L1 (two lines when it straddles) and tested with the watertight test
// on the leaf's acceptance window. Closest-hit updates go through the LVB updater. After a leaf's
// last test the ray goes back to its TRV unit, or to shading when its traversal is over.
#pragma once

#include "model/cache.h"
#include "model/lvb_updater.h"
#include "model/ray_unit.h"

#include <vector>

namespace rtsim::model {

class TrvUnit;

struct IstStats {
  uint64_t tests = 0;
  uint64_t hits = 0;
};

class IstUnit : public RayUnit {
 public:
  IstUnit(sc_core::sc_module_name name, const ModelContext& ctx, uint32_t latency, uint32_t capacity, Cache* l1,
          RayFifo* in, const std::vector<TrvUnit*>* trv, const std::vector<RayFifo*>* done_by_trv, LvbUpdater* lvb);
  const IstStats& stats() const { return stats_; }
  void register_stats(StatsRegistry& r, const std::string& prefix) const;

 protected:
  void process(uint32_t ray, Tick now) override;

 private:
  uint32_t latency_;
  Cache* l1_;
  const std::vector<TrvUnit*>* trv_;
  const std::vector<RayFifo*>* done_;  // the shading input for the rays of each TRV unit
  LvbUpdater* lvb_;
  IstStats stats_;
};

}  // namespace rtsim::model
