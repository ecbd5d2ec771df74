// LIST: fetches a leaf's record (primitive-list offset and count, and its LVB word) and then the
// primitive list itself, one line per operation (2-cycle pipeline), and passes the ray with its
// triangle ids to IST through `to_ist`.
#pragma once

#include "model/sim/stats_description.h"

#include "model/memory/cache.h"
#include "model/units/ray_unit.h"

namespace rtsim::model {

struct ListStats {
  uint64_t leaves = 0;
  uint64_t list_lines = 0;
  uint64_t prims = 0;
};

// Every ListStats field, once (model/sim/stats_description.h).
template <class V>
void describe_stats(V& v, const ListStats& s) {
  v.counter("leaves", s.leaves, "count", "leaf records fetched");
  v.counter("list_lines", s.list_lines, "count", "primitive-list lines fetched");
  v.counter("prims", s.prims, "count", "primitive ids read");
}

class ListUnit : public RayUnit {
 public:
  RayOut to_ist;

  ListUnit(sc_core::sc_module_name name, const ModelContext& ctx, const UnitTypeConfig& cfg);
  const ListStats& stats() const { return stats_; }
  void register_stats(StatsRegistry& r, const std::string& prefix) const override;

 protected:
  void process(uint32_t ray, Tick now) override;
  void admitted(uint32_t ray) override;

 private:
  // The ray met memory that is not an image: it goes on with no triangles to test.
  void fault_out(uint32_t id, ImageFault f, Tick now);

  uint32_t latency_;
  ListStats stats_;
};

}  // namespace rtsim::model
