#include "model/accelerator_config.h"

#include "common/error.h"
#include "model/energy/energy_config.h"

#include <stdexcept>
#include <string>

namespace rtsim::model {

void AcceleratorConfig::validate() const {
  RangeCheck check;
  describe(check, *this);
  if (energy != "none") {
    try {
      energy_config(energy);
    } catch (const InputError& e) {
      throw std::invalid_argument(std::string("energy: ") + e.what());
    }
  }
  const UnitTypeConfig& walk = traversal();
  if (list.l2.line_bytes != walk.l2.line_bytes || ist.l2.line_bytes != walk.l2.line_bytes)
    throw std::invalid_argument(
        "l2.line_bytes: the three L2s share one memory; expected equal line sizes");
  for (const UnitTypeConfig* u : {&walk, &list, &ist})
    if (u->l1.line_bytes > u->l2.line_bytes)
      throw std::invalid_argument("l1.line_bytes: expected <= the L2's");
  if (shading.l1.line_bytes > ist.l2.line_bytes)
    throw std::invalid_argument("shading.l1.line_bytes: expected <= the IST L2's");
  if (schedule == Schedule::kTwoPhase && culling.records_per_cycle > 0 && !write_records)
    throw std::invalid_argument(
        "culling.records_per_cycle: in two phases the culling unit reads the hit records from "
        "memory, which needs shading.write_records: true (or records_per_cycle: 0, the ideal "
        "unit)");
  if (reflection_depth < 0 || reflection_depth > 8)
    throw std::invalid_argument("reflection_depth: expected 0..8");
  if (integrator == Integrator::kPath && !path.invalid().empty())
    throw std::invalid_argument("path: " + path.invalid());
  memory_dram().validate();
}

DramConfig AcceleratorConfig::memory_dram() const {
  DramConfig d = dram;
  d.request_bytes = traversal().l2.line_bytes;  // one L2 line per memory transaction
  return d;
}

}  // namespace rtsim::model
