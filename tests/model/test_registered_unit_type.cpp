// A unit type that exists only in this test: a second shading type, a shading unit that also
// counts its operations. Its row (register_unit_type) puts it on BVH machines only, where it
// replaces the built-in shading type as the BVH unit replaces TRV: the hardware file's
// `structure` chooses it. Nothing in testbench/, reports/, scripts/ or the sampling code knows
// it, yet a frame runs with it, its pixels equal the reference tracer's, report.json lists it and
// its totals, the sweep's metrics reach it and report.md's unit table shows it.
#include "model/accelerator_units.h"
#include "model/units/shading_unit.h"
#include "reports/run_report.h"
#include "testbench/commands.h"
#include "testbench/studies/sweep_metrics.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <filesystem>

namespace rtsim::model {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

struct TallyStats {
  uint64_t operations = 0;
};

template <class V>
void describe_stats(V& v, const TallyStats& s) {
  v.counter("operations", s.operations, "count",
            "operations issued: a triangle's or a material's read, a shadow ray's end");
}

class TallyShadingUnit : public ShadingUnit {
 public:
  using ShadingUnit::ShadingUnit;
  const TallyStats& stats() const { return tally_; }
  void register_stats(StatsRegistry& r, const std::string& prefix) const override {
    ShadingUnit::register_stats(r, prefix);
    StatsRegistrar v(r, prefix);
    describe_stats(v, tally_);
  }

 protected:
  void process(uint32_t ray, Tick now) override {
    ++tally_.operations;
    ShadingUnit::process(ray, now);
  }

 private:
  TallyStats tally_;
};

// Its row: the shading stage, section and rank, on the IST's L2; BVH machines only; one work
// counter, with the per-ray figure it gives.
const bool registered = register_unit_type(
    {kShadingStage,
     "tally",
     "tally shading",
     kShadingRank,
     &AcceleratorConfig::shading,
     kIstStage,
     [](const char* name, const UnitBuild& b, uint32_t) -> std::unique_ptr<RayUnit> {
       return std::make_unique<TallyShadingUnit>(name, b.ctx, b.cfg.shading, b.frame, b.records);
     },
     Structure::kBvh,
     {{"operations", "tally_operations_per_ray"}},
     &work_totals<TallyShadingUnit>});

TEST(RegisteredUnitType, TheHardwareFilesStructureChoosesIt) {
  ASSERT_TRUE(registered);
  AcceleratorConfig cfg;
  EXPECT_STREQ(unit_types(cfg)[kShadingStage]->key, "shading");
  cfg.structure = Structure::kBvh;
  EXPECT_STREQ(unit_types(cfg)[kShadingStage]->key, "tally");
  EXPECT_STREQ(unit_types(cfg)[kTrvStage]->key, "bvh");
}

// The golden frame of the BVH machine (tests/golden/city-160x90-bvh-tni-bvh8.json) with the tally
// type shading: the same work, so the golden's every figure, the shading type's under its key.
TEST(RegisteredUnitType, AFrameRunsWithItAndEveryReportShowsIt) {
  const fs::path src = test::source_dir(), out = test::temp_dir("registered-unit");
  const json golden = json::parse(test::slurp(src / "tests/golden/city-160x90-bvh-tni-bvh8.json"));
  ASSERT_EQ(golden["args"][4], "--accel");
  RunArgs args;
  args.sources.scene_file = (src / "configs/scenes/city.yaml").string();
  args.sources.hw_file = (src / "configs/hw/bvh-tni.yaml").string();
  args.sources.run_flags["accel"] = golden["args"][5].get<std::string>();
  args.sources.run_flags["width"] = 160;
  args.sources.run_flags["height"] = 90;
  args.sources.run_flags["check"] = true;
  args.sources.run_flags["plots"] = false;
  args.out = out.string();
  args.quiet = true;
  ASSERT_EQ(run_model(args), 0);
  const json r = json::parse(test::slurp(out / "report.json"));

  EXPECT_TRUE(r["reference_check"]["image_identical"].get<bool>());
  EXPECT_EQ(r["reference_check"]["mismatched_pixels"], 0);
  json tally;
  for (const json& u : r["units"]) {
    EXPECT_NE(u["key"], "shading");
    if (u["key"] == "tally") tally = u;
  }
  ASSERT_FALSE(tally.is_null()) << r["units"];
  EXPECT_EQ(tally["label"], "tally shading");
  EXPECT_EQ(tally["stats"], "tally.total");
  EXPECT_EQ(tally["stage"], "shading");
  EXPECT_EQ(tally["per_ray"], json({{"tally_operations_per_ray", "tally.total.operations"}}));

  // Its totals: the work counter summed over its units, and the golden's figures.
  const json& stats = r["stats"];
  double operations = 0;
  for (uint32_t i = 0; i < tally["count"].get<uint32_t>(); ++i)
    operations += stats["tally" + std::to_string(i)]["operations"].get<double>();
  EXPECT_GT(operations, 0);
  EXPECT_EQ(stats["tally"]["total"]["operations"].get<double>(), operations);
  for (const auto& [key, want] : golden["expect"].items()) {
    std::string path = key;
    if (path.rfind("stats.shading.", 0) == 0) path = "stats.tally." + path.substr(14);
    EXPECT_EQ(json_number(r, path), want.get<double>()) << path;
  }

  // The sweep's metrics by its key and its stage's name, and its work per ray.
  const double b = stats["tally"]["total"]["busy_cycles"],
               s = stats["tally"]["total"]["stalled_cycles"],
               i = stats["tally"]["total"]["idle_cycles"];
  EXPECT_TRUE(is_sweep_metric("tally_busy"));
  EXPECT_TRUE(is_sweep_metric("tally_operations_per_ray"));
  EXPECT_DOUBLE_EQ(sweep_metric("tally_busy", r), b / (b + s + i));
  EXPECT_DOUBLE_EQ(sweep_metric("shading_busy", r), b / (b + s + i));
  EXPECT_DOUBLE_EQ(sweep_metric("tally_l1_hit_rate", r), json_number(r, "stats.tally.l1.hit_rate"));
  const double rays = json_number(r, "stats.bvh.total.rays_started");
  EXPECT_DOUBLE_EQ(sweep_metric("tally_operations_per_ray", r), operations / rays);
  // The built-in types' figures, from their rows too.
  EXPECT_DOUBLE_EQ(sweep_metric("nodes_per_ray", r),
                   json_number(r, "stats.bvh.total.node_fetches") / rays);
  EXPECT_DOUBLE_EQ(sweep_metric("tests_per_ray", r),
                   json_number(r, "stats.ist.total.tests") / rays);
  EXPECT_DOUBLE_EQ(sweep_metric("traversal_l2_hit_rate", r),
                   json_number(r, "stats.bvh.l2.hit_rate"));
  EXPECT_DOUBLE_EQ(sweep_metric("ist_l2_bank_stall_cycles", r),
                   json_number(r, "stats.ist.l2.bank.stall_cycles"));
  EXPECT_DOUBLE_EQ(sweep_metric("traversal_reply_queue_cycles", r),
                   json_number(r, "stats.bvh.icnt.reply.avg_queue_cycles"));

  // report.md's unit table: its label and count.
  const std::string md = test::slurp(out / "report.md");
  EXPECT_NE(md.find("| tally shading | " + std::to_string(tally["count"].get<int>()) + " |"),
            std::string::npos)
      << md;
  fs::remove_all(out);
}

}  // namespace
}  // namespace rtsim::model
