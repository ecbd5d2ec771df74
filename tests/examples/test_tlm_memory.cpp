// examples/tlm_memory: the accelerator on a plain fixed-latency TLM-2.0 memory. One ray at one
// triangle (no lights) makes five dependent memory reads (TRV: the root node; LIST: the leaf
// record, then its primitive list; IST: the triangle; shading: the material; the shading unit's
// triangle read hits in the IST L2 it shares) and one posted write (the hit record), so the frame
// takes T(L) = T(0) + 5 L cycles at 1 GHz with a latency of L ns: the closed form checked here
// over four latencies, with T(0) from a zero-latency memory. The GDDR3 model's figure differs.
#include "tests/examples/run_example.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace rtsim {
namespace {

using test::run_example;

TEST(TlmMemoryExample, OneRayTakesTheClosedFormOfAFixedLatencyMemory) {
  const std::vector<nlohmann::json> runs = run_example("triangle 0 100 250 1000");
  ASSERT_EQ(runs.size(), 5u);  // four fixed-latency memories side by side, then the GDDR3 one
  const uint64_t t0 = runs[0]["cycles"].get<uint64_t>();
  const double latencies[] = {0, 100, 250, 1000};
  for (int i = 0; i < 4; ++i) {
    const nlohmann::json& r = runs[i];
    EXPECT_EQ(r["memory"], "fixed_latency");
    EXPECT_EQ(r["latency_ns"].get<double>(), latencies[i]);
    EXPECT_EQ(r["primary_hits"], 1);
    EXPECT_EQ(r["memory_reads"], 5) << r.dump();
    EXPECT_EQ(r["memory_writes"], 1) << r.dump();
    EXPECT_EQ(r["cycles"].get<uint64_t>(), t0 + 5 * uint64_t(latencies[i])) << r.dump();
  }
  const nlohmann::json& gddr3 = runs[4];
  EXPECT_EQ(gddr3["memory"], "gddr3");
  EXPECT_EQ(gddr3["memory_reads"], 5);
  EXPECT_NE(gddr3["cycles"].get<uint64_t>(), runs[1]["cycles"].get<uint64_t>());
  EXPECT_GT(gddr3["cycles"].get<uint64_t>(), t0);  // a DRAM read is never free
}

TEST(TlmMemoryExample, AFrameOnAFixedLatencyMemoryRenders) {
  const std::vector<nlohmann::json> runs = run_example("city 40");
  ASSERT_EQ(runs.size(), 2u);
  EXPECT_EQ(runs[0]["primary_hits"], runs[1]["primary_hits"]);  // the same frame, another memory
  EXPECT_GT(runs[0]["primary_hits"].get<uint64_t>(), 0u);
  EXPECT_NE(runs[0]["cycles"], runs[1]["cycles"]);
}

}  // namespace
}  // namespace rtsim
