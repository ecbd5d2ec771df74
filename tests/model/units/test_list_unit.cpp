// The LIST unit on its own (tests/model/units/unit_bench.h): a ray at a leaf gets the leaf's record
// (its LVB word among it) and then its primitive list, one line per operation (2-cycle pipeline),
// and leaves for IST with exactly the leaf's triangle ids. Timing from the documented rules: each
// operation completes at max(issue, delivery) + 2; a cold line costs kMiss, an L1 hit kL1Hit; so
// a leaf whose list spans `lines` lines leaves after (1 + lines) such steps. Two warm rays back
// to back leave one cycle apart. The busy/stalled/idle cycles add up to the elapsed ones. One
// simulation for the file (SystemC elaborates once per process), built by the first test.
#include "model/units/list_unit.h"

#include "tests/model/units/unit_bench.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <memory>

namespace rtsim::model {
namespace {

using namespace bench;

// A cluster of 20 overlapping triangles around x = 0 (no split separates them: one leaf of 20,
// a list of 80 bytes, more than one line) and a lone triangle at x = 10.
Scene cluster_and_lone() {
  Scene s;
  s.add_material(Material{});
  for (int k = 0; k < 20; ++k)
    s.triangles.push_back(
        {Vec3(-1.f, -1.f, -5.f), Vec3(1.f, -1.f, -5.f), Vec3(0.f, 1.f + 0.01f * k, -5.f), 0});
  s.triangles.push_back({Vec3(9.f, -1.f, -5.f), Vec3(11.f, -1.f, -5.f), Vec3(10.f, 1.f, -5.f), 0});
  return s;
}

constexpr uint64_t kLatency = 2;  // the LIST pipeline (the paper's)
constexpr uint32_t kLvb = 0x5;    // the cluster leaf's LVB word, written into the image
constexpr uint64_t kCold = 10;    // one ray, every line cold
constexpr uint64_t kWarm = 300;   // two rays at once, every line in L1

struct ListBench : Bench {
  ListBench(sc_core::sc_module_name name, const MemoryImage& image)
      : Bench(name, image, config()), to_ist("to_ist", 64, nullptr), list("list0", ctx, cfg.list) {
    attach(list.mem_side, kListStage, 0);
    list.to_ist.bind(to_ist);
  }
  RayFifo to_ist;
  ListUnit list;
};

struct Scenario {
  Scene scene = cluster_and_lone();
  KdTree tree = build_kdtree(scene.triangles);
  MemoryImage image = lvb_image();
  std::unique_ptr<ListBench> b;
  uint32_t cold = 0, warm0 = 0, warm1 = 0;
  std::vector<std::pair<uint32_t, uint64_t>> out;
  UnitStats unit;

  MemoryImage lvb_image() {
    MemoryImage m(scene, tree);
    m.set_leaf_lvb(leaf(), kLvb);
    return m;
  }
  uint32_t leaf() const { return locate_leaf(tree, Vec3(0.f, 0.f, -5.f)); }
  // Lines of the leaf's primitive list (the prims section is line-aligned).
  uint64_t lines() const {
    const KdLeaf& l = tree.leaves[leaf()];
    const uint64_t first = image.prim_addr(l.first), end = image.prim_addr(l.first + l.count);
    return (end - 1) / 64 - first / 64 + 1;
  }
  uint32_t ray_at_leaf(uint64_t cycle) {
    const uint32_t id = b->add_ray({Vec3(0.f, 0.f, 0.f), Vec3(0.f, 0.f, -1.f)});
    EXPECT_TRUE(walk_to_leaf(image, b->pool[id], b->ctx.abs_eps));
    b->feed(&b->list.in, id, cycle);
    return id;
  }

  Scenario() {
    b = std::make_unique<ListBench>("bench", image);
    cold = ray_at_leaf(kCold);
    warm0 = ray_at_leaf(kWarm);
    warm1 = ray_at_leaf(kWarm);
    test::simulate();
    b->list.finish_accounting(at(kEndCycle));
    out = Bench::drain(b->to_ist);
  }
};

Scenario& run() {
  static Scenario r;
  return r;
}

TEST(ListUnit, EmitsTheLeafsPrimitiveIdsAndItsLvbWord) {
  Scenario& r = run();
  const KdLeaf& l = r.tree.leaves[r.leaf()];
  ASSERT_EQ(l.count, 20u) << "the cluster should be one leaf";
  ASSERT_GE(r.lines(), 2u) << "the list should span lines";
  const std::vector<uint32_t> expected(r.tree.prims.begin() + l.first,
                                       r.tree.prims.begin() + l.first + l.count);
  ASSERT_EQ(r.out.size(), 3u);
  for (const auto& [ray, cycle] : r.out) {
    const RayState& s = r.b->pool[ray];
    EXPECT_EQ(s.trv.walk.leaf, r.leaf());
    EXPECT_EQ(s.list.tris, expected);
    EXPECT_EQ(s.list.leaf_lvb, kLvb);
  }
  EXPECT_EQ(r.b->list.stats().leaves, 3u);
  EXPECT_EQ(r.b->list.stats().list_lines, 3 * r.lines());
  EXPECT_EQ(r.b->list.stats().prims, 3u * l.count);
}

TEST(ListUnit, OneLinePerOperationWithTheL1sDeliveryAndThePipelineLatency) {
  Scenario& r = run();
  ASSERT_EQ(r.out.size(), 3u);
  // Cold: the leaf record, then each list line, each a cold line: kMiss, then the pipeline.
  EXPECT_EQ(r.out[0].first, r.cold);
  EXPECT_EQ(r.out[0].second, kCold + (1 + r.lines()) * (kMiss + kLatency));
  // Warm: every line hits in L1; the second ray issues each step one cycle after the first.
  EXPECT_EQ(r.out[1].first, r.warm0);
  EXPECT_EQ(r.out[1].second, kWarm + (1 + r.lines()) * (kL1Hit + kLatency));
  EXPECT_EQ(r.out[2].first, r.warm1);
  EXPECT_EQ(r.out[2].second, kWarm + 1 + (1 + r.lines()) * (kL1Hit + kLatency));
  EXPECT_EQ(r.b->list.l1().stats().misses, 1 + r.lines());
  EXPECT_EQ(r.b->ram.reads, 1 + r.lines());
}

TEST(ListUnit, BusyStalledAndIdleCyclesAddUpToTheElapsedCycles) {
  Scenario& r = run();
  const uint64_t steps = 1 + r.lines();
  const UnitStats& s = r.b->list.unit_stats();
  // The cold ray issues every step twice (the miss, then the re-issue when its line came); a warm
  // ray once. The unit holds work from a ray's first issue to its last (the emit).
  const uint64_t cold_span = steps * kMiss + (steps - 1) * kLatency + 1;
  // The second ray's last issue
  const uint64_t warm_span = 1 + (steps - 1) * (kL1Hit + kLatency) + 1;
  EXPECT_EQ(s.busy_cycles, 2 * steps + 2 * steps);
  EXPECT_EQ(s.stalled_cycles, cold_span + warm_span - s.busy_cycles);
  EXPECT_EQ(s.idle_cycles, kEndCycle - cold_span - warm_span);
  EXPECT_EQ(s.busy_cycles + s.stalled_cycles + s.idle_cycles, kEndCycle);
}

}  // namespace
}  // namespace rtsim::model
