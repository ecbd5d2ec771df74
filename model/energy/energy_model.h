// A frame's energy: the counts the model already keeps, priced (the accelerator's pricing mode,
// beside its timing and its functional pass). Nothing here counts: the units' and caches' named
// statistics give the work, the unit table's rows say which operation prices each counter
// (accelerator_units.h, WorkCounter::op), the caches' and links' configurations give the arrays
// and bytes, and the DRAM's command counts and cycles with a row open give its Micron terms
// (dram_energy.h). docs/energy.md gives the model and its sources.
//   dynamic: operations, SRAM reads and writes (fills), link bytes, DRAM commands
//   static:  SRAM leakage over the frame, the DRAM's background
#pragma once

#include "model/accelerator_config.h"
#include "model/energy/energy_config.h"
#include "model/memory/dram_energy.h"
#include "model/units/ray_state.h"

#include <nlohmann/json.hpp>

#include <array>
#include <string>
#include <vector>

namespace rtsim::model {

// One priced part of the machine: a unit type's operations, a cache level of a unit type, a
// crossbar. pJ.
struct EnergyPart {
  std::string key;    // its statistics' prefix (trv, trv.l1, trv.icnt)
  std::string label;  // its name in reports
  std::string level;  // a cache's level (L1, L2); else empty
  double dynamic_pj = 0, static_pj = 0;
  uint64_t reads = 0, writes = 0;  // a cache's priced accesses and fills; a link's bytes in reads
  double total_pj() const { return dynamic_pj + static_pj; }
};

struct FrameEnergy {
  std::string node;  // the energy file's
  double frame_ns = 0;
  std::vector<EnergyPart> units, caches, links;
  DramEnergy dram;  // its background is static, the rest dynamic
  // By ray type (RayType's order), the frame's energy shared out (docs/energy.md, "By ray
  // type"): what a type's rays alone cause (making a primary ray, shading a hit of the type,
  // sampling a bounce, deciding and making a shadow ray); the walk-driven rest (traversal, LIST
  // and IST operations, caches, crossbars, DRAM commands) by the type's share of the node fetches;
  // the static energy by the type's share of the dynamic. They add up to total_pj().
  std::array<double, kRayTypes> ray_type_pj{};
  PerRayType rays{};  // the rays of each type the frame traced
  double dynamic_pj() const;
  double static_pj() const;
  double total_pj() const { return dynamic_pj() + static_pj(); }
};

// `stats`: the frame's named statistics (report.json's `stats`); `frame_ns`: the time they span;
// `rays`: the rays of each type the frame traced (shadow rays: those not culled). A statistic the
// pricing needs and the model did not register is an internal error.
FrameEnergy price_frame(const AcceleratorConfig& cfg, const EnergyConfig& energy,
                        const nlohmann::json& stats, double frame_ns, const PerRayType& rays);

// report.json's `energy`: the parts in uJ, their sums, average power, energy per ray, and by ray
// type (`nee`: a path-traced frame's shadow rays, next-event estimation).
nlohmann::json energy_json(const FrameEnergy& e, const DramConfig& dram, Integrator integrator);

}  // namespace rtsim::model
