// The accelerator's unit types, one row each. From a row the netlist builds a type's units, binds
// their memory side, declares their same-time rank, observes them (watchdog, VCD) and registers
// their statistics and totals; report.json lists the rows (`units`, `caches`), and the reports and
// figures iterate that list. What a row cannot say, a ray's path between the types, is bound in
// model/accelerator.cpp. docs/adding-a-unit.md walks through adding a type.
#pragma once

#include "model/accelerator_config.h"
#include "model/units/frame_buffer.h"
#include "model/units/hit_record.h"
#include "model/units/model_context.h"
#include "model/units/ray_unit.h"

#include <nlohmann/json.hpp>

#include <array>
#include <memory>
#include <optional>

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

// A type of ray unit (model/units/ray_unit.h). A machine has one type per stage: the traversal
// stage's is TRV or the BVH unit, by `structure`.
struct RayUnitType {
  Stage stage;        // its place on a ray's path, and its entry in a ray's state (ray_state.h)
  const char* key;    // its units are <key><i>; statistics <key>.*; its hardware file section
  const char* label;  // its name in reports
  Rank rank;
  UnitTypeConfig AcceleratorConfig::*config;
  // Whose L2 its L1s reach: its own (the type's `l2` section, shared or private), or another
  // type's, shared (shading: the IST's).
  Stage l2_of;
  // Builds unit `index` of the type, named `name`, in the current module's scope.
  std::unique_ptr<RayUnit> (*make)(const char* name, const UnitBuild& b, uint32_t index);
  // The machines that have this type: what their traversal units walk (any, for the others).
  std::optional<Structure> only_for;
};

// Every type, in stage order.
extern const std::array<RayUnitType, kStages + 1> kRayUnitTypes;

// The types of the machine `cfg` describes, indexed by stage.
using UnitTypes = std::array<const RayUnitType*, kStages>;
UnitTypes unit_types(const AcceleratorConfig& cfg);

// The unit types a report lists, in its order ({key, label, count, stats}: `stats` the prefix of
// the type's busy/stalled/idle cycles, summed over its units), and the caches it lists ({key,
// unit, label, level}: `key` the statistics prefix, a type's total over its units).
nlohmann::json report_units(const AcceleratorConfig& cfg);
nlohmann::json report_caches(const AcceleratorConfig& cfg);

}  // namespace rtsim::model
