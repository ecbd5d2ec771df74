#include "model/sim/stats_registry.h"

#include <gtest/gtest.h>

namespace rtsim::model {
namespace {

TEST(StatsRegistry, DumpsCountersAndFormulasByDottedName) {
  StatsRegistry r;
  uint64_t hits = 3, misses = 1;
  r.counter("trv.l1.hits", &hits, "count", "L1 hits");
  r.counter("trv.l1.misses", &misses, "count", "L1 misses");
  r.formula(
      "trv.l1.hit_rate", [&] { return double(hits) / double(hits + misses); }, "ratio",
      "hits / accesses");
  hits = 6;  // counters are read at dump time
  const nlohmann::json j = r.values();
  EXPECT_EQ(j["trv"]["l1"]["hits"], 6);
  EXPECT_EQ(j["trv"]["l1"]["misses"], 1);
  EXPECT_DOUBLE_EQ(j["trv"]["l1"]["hit_rate"].get<double>(), 6.0 / 7.0);
  EXPECT_DOUBLE_EQ(r.value("trv.l1.hits"), 6.0);
  EXPECT_EQ(r.glossary().at("trv.l1.misses").description, "L1 misses");
  EXPECT_EQ(r.glossary().at("trv.l1.hit_rate").unit, "ratio");
  EXPECT_THROW(r.counter("trv.l1.hits", &hits, "count", "again"), std::logic_error);
  EXPECT_THROW(r.value("nope"), std::out_of_range);
}

}  // namespace
}  // namespace rtsim::model
