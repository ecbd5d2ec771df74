#include "model/accelerator_units.h"

#include "model/units/bvh_unit.h"
#include "model/units/ist_unit.h"
#include "model/units/list_unit.h"
#include "model/units/shading_unit.h"
#include "model/units/trv_unit.h"

#include <deque>

namespace rtsim::model {

namespace {

// Built in, in stage order.
std::deque<RayUnitType> built_in() {
  // The types' work counters (their totals), with the per-ray figures they give; here, not
  // globals, so that a type registered by another file's static initialiser finds them built.
  // Node fetches by ray type share the walk-driven energy among ray types (model/energy/).
  const std::vector<WorkCounter> by_type = {{"node_fetches_primary"},
                                            {"node_fetches_reflection"},
                                            {"node_fetches_shadow"},
                                            {"node_fetches_bounce"}};
  std::vector<WorkCounter> trv_work = {{"node_fetches", "nodes_per_ray", "kd_step"},
                                       {"rays_started", nullptr, "ray_setup"}};
  std::vector<WorkCounter> bvh_work = {{"node_fetches", "nodes_per_ray"},
                                       {"box_tests", nullptr, "box_test"},
                                       {"leaves"},
                                       {"rays_started", nullptr, "ray_setup"},
                                       {"stack_pushes"},
                                       {"stack_pops"},
                                       {"stack_spills"},
                                       {"stack_refills"}};
  for (std::vector<WorkCounter>* w : {&trv_work, &bvh_work})
    w->insert(w->end(), by_type.begin(), by_type.end());
  const std::vector<WorkCounter> list_work = {{"leaves", "leaves_per_ray"},
                                              {"prims", nullptr, "list_entry"}};
  const std::vector<WorkCounter> ist_work = {{"tests", "tests_per_ray", "triangle_test"},
                                             {"hits", nullptr, "triangle_hit"}};
  // Every hit is shaded; a path's bounce is sampled at the hit it leaves.
  const std::vector<WorkCounter> shading_work = {{"primary_rays"},
                                                 {"primary_hits", nullptr, "shade"},
                                                 {"reflection_rays"},
                                                 {"reflection_hits", nullptr, "shade"},
                                                 {"bounce_hits", nullptr, "shade"},
                                                 {"bounce_rays", nullptr, "bounce_sample"}};
  return {
      {kTrvStage, "trv", "TRV", kTrvRank, &AcceleratorConfig::trv, kTrvStage,
       [](const char* name, const UnitBuild& b, uint32_t i) -> std::unique_ptr<RayUnit> {
         return std::make_unique<TrvUnit>(name, b.ctx, b.cfg.trv, i);
       },
       Structure::kKdTree, trv_work, &work_totals<TrvUnit>, "rays_started"},
      {kTrvStage, "bvh", "BVH", kTrvRank, &AcceleratorConfig::bvh, kTrvStage,
       [](const char* name, const UnitBuild& b, uint32_t i) -> std::unique_ptr<RayUnit> {
         return std::make_unique<BvhUnit>(name, b.ctx, b.cfg.bvh, b.cfg.bvh_walk, i);
       },
       Structure::kBvh, bvh_work, &work_totals<BvhUnit>, "rays_started"},
      {kListStage, "list", "LIST", kListRank, &AcceleratorConfig::list, kListStage,
       [](const char* name, const UnitBuild& b, uint32_t) -> std::unique_ptr<RayUnit> {
         return std::make_unique<ListUnit>(name, b.ctx, b.cfg.list);
       },
       std::nullopt, list_work, &work_totals<ListUnit>},
      {kIstStage, "ist", "IST", kIstRank, &AcceleratorConfig::ist, kIstStage,
       [](const char* name, const UnitBuild& b, uint32_t) -> std::unique_ptr<RayUnit> {
         return std::make_unique<IstUnit>(name, b.ctx, b.cfg.ist);
       },
       std::nullopt, ist_work, &work_totals<IstUnit>},
      {kShadingStage, "shading", "shading", kShadingRank, &AcceleratorConfig::shading, kIstStage,
       [](const char* name, const UnitBuild& b, uint32_t) -> std::unique_ptr<RayUnit> {
         return std::make_unique<ShadingUnit>(name, b.ctx, b.cfg.shading, b.frame, b.records);
       },
       std::nullopt, shading_work, &work_totals<ShadingUnit>},
  };
}

// A deque: adding a type leaves the others where they are.
std::deque<RayUnitType>& registry() {
  static std::deque<RayUnitType> types = built_in();
  return types;
}

}  // namespace

const char* stage_name(Stage s) {
  static const char* const names[kStages] = {"traversal", "list", "ist", "shading"};
  return names[s];
}

bool register_unit_type(RayUnitType type) {
  registry().push_back(std::move(type));
  return true;
}

UnitTypes unit_types(const AcceleratorConfig& cfg) {
  UnitTypes types{};
  for (const RayUnitType& t : registry())
    if (!t.only_for || *t.only_for == cfg.structure) types[t.stage] = &t;
  return types;
}

nlohmann::json report_units(const AcceleratorConfig& cfg) {
  nlohmann::json units = nlohmann::json::array();
  units.push_back(
      {{"key", "raygen"}, {"label", "ray generator"}, {"count", 1}, {"stats", "raygen"}});
  for (const RayUnitType* t : unit_types(cfg)) {
    const std::string total = std::string(t->key) + ".total";
    nlohmann::json u = {{"key", t->key},
                        {"label", t->label},
                        {"count", (cfg.*t->config).count},
                        {"stats", total},
                        {"stage", stage_name(t->stage)}};
    for (const WorkCounter& w : t->work)
      if (w.per_ray) u["per_ray"][w.per_ray] = total + "." + w.counter;
    if (t->rays) u["rays"] = total + "." + t->rays;
    units.push_back(std::move(u));
  }
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
