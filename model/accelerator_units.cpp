#include "model/accelerator_units.h"

#include "model/units/bvh_unit.h"
#include "model/units/ist_unit.h"
#include "model/units/list_unit.h"
#include "model/units/shading_unit.h"
#include "model/units/trv_unit.h"

namespace rtsim::model {

const std::array<RayUnitType, kStages + 1> kRayUnitTypes = {{
    {kTrvStage, "trv", "TRV", kTrvRank, &AcceleratorConfig::trv, kTrvStage,
     [](const char* name, const UnitBuild& b, uint32_t i) -> std::unique_ptr<RayUnit> {
       return std::make_unique<TrvUnit>(name, b.ctx, b.cfg.trv, i);
     },
     Structure::kKdTree},
    {kTrvStage, "bvh", "BVH", kTrvRank, &AcceleratorConfig::bvh, kTrvStage,
     [](const char* name, const UnitBuild& b, uint32_t i) -> std::unique_ptr<RayUnit> {
       return std::make_unique<BvhUnit>(name, b.ctx, b.cfg.bvh, b.cfg.bvh_walk, i);
     },
     Structure::kBvh},
    {kListStage, "list", "LIST", kListRank, &AcceleratorConfig::list, kListStage,
     [](const char* name, const UnitBuild& b, uint32_t) -> std::unique_ptr<RayUnit> {
       return std::make_unique<ListUnit>(name, b.ctx, b.cfg.list);
     },
     std::nullopt},
    {kIstStage, "ist", "IST", kIstRank, &AcceleratorConfig::ist, kIstStage,
     [](const char* name, const UnitBuild& b, uint32_t) -> std::unique_ptr<RayUnit> {
       return std::make_unique<IstUnit>(name, b.ctx, b.cfg.ist);
     },
     std::nullopt},
    {kShadingStage, "shading", "shading", kShadingRank, &AcceleratorConfig::shading, kIstStage,
     [](const char* name, const UnitBuild& b, uint32_t) -> std::unique_ptr<RayUnit> {
       return std::make_unique<ShadingUnit>(name, b.ctx, b.cfg.shading, b.frame, b.records);
     },
     std::nullopt},
}};

UnitTypes unit_types(const AcceleratorConfig& cfg) {
  UnitTypes types{};
  for (const RayUnitType& t : kRayUnitTypes)
    if (!t.only_for || *t.only_for == cfg.structure) types[t.stage] = &t;
  return types;
}

nlohmann::json report_units(const AcceleratorConfig& cfg) {
  nlohmann::json units = nlohmann::json::array();
  units.push_back(
      {{"key", "raygen"}, {"label", "ray generator"}, {"count", 1}, {"stats", "raygen"}});
  for (const RayUnitType* t : unit_types(cfg))
    units.push_back({{"key", t->key},
                     {"label", t->label},
                     {"count", (cfg.*t->config).count},
                     {"stats", std::string(t->key) + ".total"}});
  units.push_back(
      {{"key", "culling"}, {"label", "shadow culling"}, {"count", 1}, {"stats", "culling"}});
  return units;
}

nlohmann::json report_caches(const AcceleratorConfig& cfg) {
  nlohmann::json caches = nlohmann::json::array();
  for (const RayUnitType* t : unit_types(cfg)) {
    caches.push_back({{"key", std::string(t->key) + ".l1"},
                      {"unit", t->key},
                      {"label", t->label},
                      {"level", "L1"}});
    if (t->l2_of == t->stage)
      caches.push_back({{"key", std::string(t->key) + ".l2"},
                        {"unit", t->key},
                        {"label", t->label},
                        {"level", "L2"}});
  }
  return caches;
}

}  // namespace rtsim::model
