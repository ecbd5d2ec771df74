// The accelerator's unit types, one row each. From a row the netlist builds a type's units, binds
// their memory side, declares their same-time rank, observes them (watchdog, VCD) and registers
// their statistics and totals; report.json lists the rows (`units`, `caches`), and the reports and
// figures iterate that list. What a row cannot say, a ray's path between the types, is bound in
// model/accelerator.cpp. docs/adding-a-unit.md walks through adding a type.
#pragma once

#include "model/accelerator_config.h"
#include "model/sim/stats_description.h"
#include "model/units/frame_buffer.h"
#include "model/units/hit_record.h"
#include "model/units/model_context.h"
#include "model/units/ray_unit.h"

#include <nlohmann/json.hpp>

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

namespace rtsim::model {

// The calendar's same-time order (docs/model-design.md, "Same-time order"): among the blocks due
// at one time the memory acts first, then the units from the end of a ray's walk (IST) back to
// its start (TRV), so that a slot a unit frees is seen by its producer in the same cycle; then
// shading, the generator and the culling unit, which start rays, and the watchdog, which looks
// at what all the others did. Units of one type act in the order of their index.
enum Rank : uint32_t {
  kDramRank,
  kMemoryPortRank,
  kIstRank,
  kListRank,
  kTrvRank,
  kShadingRank,
  kRayGeneratorRank,
  kCullingRank,
  kWatchdogRank,
};

// What a row's factory may give a unit: the accelerator's shared state.
struct UnitBuild {
  const ModelContext& ctx;
  const AcceleratorConfig& cfg;
  FrameBuffer* frame;
  const HitRecordRegion& records;
};

// A counter of a type's units that its totals sum (`<key>.total.<counter>`), the figure per ray
// it gives, if any (a sweep metric, the total over the rays the machine's walks started), and the
// operation that prices each count, if any (model/energy/energy_config.h: an energy file's
// `operations`).
struct WorkCounter {
  const char* counter;
  const char* per_ray = nullptr;  // null: none
  const char* op = nullptr;       // null: not priced
};

using UnitList = std::vector<std::unique_ptr<RayUnit>>;
// Registers a type's work totals over its units (work_totals<U> below).
using WorkTotals = void (*)(StatsRegistry& r, const std::string& key, const UnitList& units,
                            const std::vector<WorkCounter>& work);

// A type of ray unit (model/units/ray_unit.h). A machine has one type per stage: the traversal
// stage's is TRV or the BVH unit, by `structure`; a registered type may take a stage's place.
struct RayUnitType {
  Stage stage;        // its place on a ray's path, and its entry in a ray's state (ray_state.h)
  const char* key;    // its units are <key><i>; statistics <key>.*
  const char* label;  // its name in reports
  Rank rank;
  UnitTypeConfig AcceleratorConfig::*config;  // its section of the hardware file
  // Whose L2 its L1s reach: its own (the type's `l2` section, shared or private), or another
  // type's, shared (shading: the IST's).
  Stage l2_of;
  // Builds unit `index` of the type, named `name`, in the current module's scope.
  std::unique_ptr<RayUnit> (*make)(const char* name, const UnitBuild& b, uint32_t index);
  // The machines that have this type: what their traversal units walk (any, for the others).
  std::optional<Structure> only_for;
  // Its work: the counters its totals sum, with the per-ray figures they give and the operations
  // that price them (`totals` registers them, work_totals<its unit class>); and the counter of the
  // rays it starts, which every per-ray figure divides (the traversal types'; null for the others).
  std::vector<WorkCounter> work = {};
  WorkTotals totals = nullptr;
  const char* rays = nullptr;
};

// The table holds the built-in types (model/accelerator_units.cpp), then those registered.
// Adds a type (a test's, say) before any accelerator is built. Of the types a machine has for a
// stage, the last added is the one it builds: a type registered for a stage replaces the built-in
// one on the machines its `only_for` names. Returns true (for a static initialiser).
bool register_unit_type(RayUnitType type);

// A stage by name, as the report lists it (and the sweep's structure-neutral metrics and the
// functional pass's features): traversal, list, ist, shading.
const char* stage_name(Stage s);

// The types of the machine `cfg` describes, indexed by stage.
using UnitTypes = std::array<const RayUnitType*, kStages>;
UnitTypes unit_types(const AcceleratorConfig& cfg);

// <key>.total.<counter> for each of `work`, summed over `units`, all of class U: the counters of
// U::stats(), described once (describe_stats).
template <class U>
void work_totals(StatsRegistry& r, const std::string& key, const UnitList& units,
                 const std::vector<WorkCounter>& work) {
  using S = std::decay_t<decltype(std::declval<const U&>().stats())>;
  std::vector<const S*> parts;
  for (const auto& u : units) parts.push_back(&static_cast<const U&>(*u).stats());
  std::vector<std::string> names;
  for (const WorkCounter& w : work) names.push_back(w.counter);
  register_totals(r, key + ".total", "all " + key + " units: ", parts, names,
                  [](auto& v, const S& s) { describe_stats(v, s); });
}

// The unit types a report lists, in its order ({key, label, count, stats}: `stats` the prefix of
// the type's busy/stalled/idle cycles, summed over its units; a ray unit type adds its `stage`
// ("traversal", "list", "ist", "shading"), its work figures `per_ray` ({metric: statistic}) and,
// on the traversal stage, `rays`, the statistic they divide), and the caches it lists ({key,
// unit, label, level}: `key` the statistics prefix, a type's total over its units).
nlohmann::json report_units(const AcceleratorConfig& cfg);
nlohmann::json report_caches(const AcceleratorConfig& cfg);

}  // namespace rtsim::model
