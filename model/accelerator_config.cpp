#include "model/accelerator_config.h"

#include <stdexcept>
#include <string>

namespace rtsim::model {

namespace {

void validate_type(const UnitTypeConfig& u, const std::string& name, bool has_l2) {
  auto bad = [&](const std::string& field, const std::string& what) {
    throw std::invalid_argument(name + "." + field + ": " + what);
  };
  if (u.count < 1 || u.count > 1024) bad("count", "expected 1..1024");
  if (u.latency < 1 || u.latency > 10000) bad("latency", "expected 1..10000 cycles");
  if (u.capacity < 1 || u.capacity > 65536) bad("capacity", "expected 1..65536 rays");
  if (u.fifo_depth < 1 || u.fifo_depth > 65536) bad("fifo_depth", "expected 1..65536");
  try {
    u.l1.validate();
  } catch (const std::invalid_argument& e) {
    bad("l1", e.what());
  }
  try {
    u.link.validate();
  } catch (const std::invalid_argument& e) {
    bad("link", e.what());
  }
  if (has_l2) {
    try {
      u.l2.validate();
    } catch (const std::invalid_argument& e) {
      bad("l2", e.what());
    }
  }
}

}  // namespace

void AcceleratorConfig::validate() const {
  if (!(clock_ghz > 0.01 && clock_ghz <= 100)) throw std::invalid_argument("clock_ghz: expected (0.01, 100]");
  validate_type(trv, "trv", true);
  validate_type(list, "list", true);
  validate_type(ist, "ist", true);
  validate_type(shading, "shading", false);
  if (shading.count > 64) throw std::invalid_argument("shading.count: expected 1..64");
  if (list.l2.line_bytes != trv.l2.line_bytes || ist.l2.line_bytes != trv.l2.line_bytes)
    throw std::invalid_argument("l2.line_bytes: the three L2s share one memory; expected equal line sizes");
  for (const UnitTypeConfig* u : {&trv, &list, &ist})
    if (u->l1.line_bytes > u->l2.line_bytes) throw std::invalid_argument("l1.line_bytes: expected <= the L2's");
  if (shading.l1.line_bytes > ist.l2.line_bytes) throw std::invalid_argument("shading.l1.line_bytes: expected <= the IST L2's");
  try {
    memory_link.validate();
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("memory_link: ") + e.what());
  }
  if (ray_pool < 1 || ray_pool > (1u << 24)) throw std::invalid_argument("ray_pool: expected 1..16777216");
  if (culling.records_per_cycle > 64) throw std::invalid_argument("culling.records_per_cycle: expected 0 (unlimited) .. 64");
  if (culling.prefetch < 1 || culling.prefetch > 65536) throw std::invalid_argument("culling.prefetch: expected 1..65536");
  if (schedule == Schedule::kTwoPhase && culling.records_per_cycle > 0 && !write_records)
    throw std::invalid_argument(
        "culling.records_per_cycle: in two phases the culling unit reads the hit records from memory, which needs "
        "shading.write_records: true (or records_per_cycle: 0, the ideal unit)");
  if (raygen_rays_per_cycle < 1 || raygen_rays_per_cycle > 64)
    throw std::invalid_argument("raygen.rays_per_cycle: expected 1..64");
  if (tile < 1 || tile > 4096) throw std::invalid_argument("tile: expected 1..4096");
  if (watchdog_cycles < 1000) throw std::invalid_argument("watchdog_cycles: expected at least 1000");
  if (reflection_depth < 0 || reflection_depth > 8) throw std::invalid_argument("reflection_depth: expected 0..8");
  DramConfig d = dram;
  d.request_bytes = trv.l2.line_bytes;
  d.validate();
}

}  // namespace rtsim::model
