// A TRV unit whose pipeline takes a new operation every 2 cycles (initiation_interval 2), on its
// own (tests/model/units/unit_bench.h): four rays arriving together walk the same nodes, all L1
// hits after a first ray warmed the lines. With an interval of 1 ray k leaves at
// start + k + nodes x (hit + latency) (test_trv_unit.cpp); with 2 its operations issue 2 cycles
// apart, so ray k leaves 2k cycles after the start plus the same walk: 4 rays x 2 cycles fit in
// one step (hit + latency = 9 cycles), so no later operation waits for the interval. A unit with
// one ray at a time (interval = latency) serialises: every operation waits for the previous
// one's issue + 8. SystemC elaborates once per process: both benches run in one simulation.
#include "model/units/trv_unit.h"

#include "tests/model/units/unit_bench.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <memory>

namespace rtsim::model {
namespace {

using namespace bench;

constexpr uint32_t kTarget = 2;
constexpr uint64_t kLatency = 8;
constexpr uint64_t kStep = kL1Hit + kLatency;
constexpr uint64_t kWarm = 10;    // the first ray, warming the L1
constexpr uint64_t kBatch = 300;  // four rays at once
constexpr int kRays = 4;

struct OneTrv : Bench {
  OneTrv(sc_core::sc_module_name name, const MemoryImage& image, const AcceleratorConfig& c)
      : Bench(name, image, c), list("list0", 64, nullptr), trv("trv0", ctx, cfg.trv, 0) {
    attach(trv.mem_side, kTrvStage, 0);
    trv.to_list.bind(list);
    trv.to_shading.bind(done);
  }
  RayFifo list;
  TrvUnit trv;
};

struct Scenario {
  Scene scene = row_of_triangles();
  KdTree tree = build_kdtree(scene.triangles);
  MemoryImage image{scene, tree};
  std::unique_ptr<OneTrv> pipelined, one_at_a_time;  // interval 2, and interval = latency
  std::vector<std::pair<uint32_t, uint64_t>> out2, out8;

  std::unique_ptr<OneTrv> bench(const char* name, uint32_t interval) {
    AcceleratorConfig c = config();
    c.trv.count = 1;
    c.trv.initiation_interval = interval;
    auto b = std::make_unique<OneTrv>(name, image, c);
    const float x = 4.f * kTarget;
    b->feed(&b->trv.in, b->add_ray(down_at(x)), kWarm);
    for (int k = 0; k < kRays; ++k) b->feed(&b->trv.in, b->add_ray(down_at(x)), kBatch);
    return b;
  }
  Scenario() {
    pipelined = bench("interval2", 2);
    one_at_a_time = bench("interval8", uint32_t(kLatency));
    test::simulate();
    out2 = Bench::drain(pipelined->list);
    out8 = Bench::drain(one_at_a_time->list);
  }
  // The nodes a ray aimed at the target visits: the leaf's depth plus one.
  uint64_t nodes() const {
    uint32_t depth = 0;
    locate_leaf(tree, Vec3(4.f * kTarget, 0.f, -5.f), &depth);
    return depth + 1;
  }
};

Scenario& run() {
  static Scenario r;
  return r;
}

TEST(InitiationInterval, TwoCyclesApartTheRaysOfABatchLeaveTwoCyclesApart) {
  Scenario& r = run();
  ASSERT_EQ(r.out2.size(), 1u + kRays);
  ASSERT_GE(r.nodes(), 2u);
  for (int k = 0; k < kRays; ++k)
    EXPECT_EQ(r.out2[1 + k].second, kBatch + 2 * k + r.nodes() * kStep) << "ray " << k;
}

TEST(InitiationInterval, OneOperationAtATimeSerialisesTheBatch) {
  Scenario& r = run();
  ASSERT_EQ(r.out8.size(), 1u + kRays);
  // Every operation of the batch issues kLatency after the previous one (the interval is longer
  // than the gaps a ready ray leaves), the last one the batch's last node.
  const uint64_t ops = kRays * r.nodes();
  EXPECT_EQ(r.out8.back().second, kBatch + (ops - 1) * kLatency + kL1Hit + kLatency);
  for (int k = 1; k < kRays; ++k) EXPECT_GT(r.out8[1 + k].second, r.out8[k].second);
  // The same operations in both, only later.
  const uint64_t busy = r.pipelined->trv.unit_stats().busy_cycles;
  EXPECT_EQ(r.one_at_a_time->trv.unit_stats().busy_cycles, busy);
  EXPECT_GE(busy, (1 + kRays) * r.nodes());
}

}  // namespace
}  // namespace rtsim::model
