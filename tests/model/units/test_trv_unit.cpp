// The TRV unit on its own (tests/model/units/unit_bench.h): a ray walks a small SAH kd-tree to the
// leaf that holds the triangle it points at, one node per operation, and leaves for LIST when the
// closed form of the documented rules says: the pipeline latency (8), one operation per cycle,
// and each node's delivery (8 nodes a line: a line's first node comes from memory, the rest hit
// in L1). Two TRV units share one L2, so on the second unit a line's first node is an L1 miss
// that hits in the L2. The busy/stalled/idle accounting must add up to the elapsed cycles.
// SystemC elaborates once per process: every scenario runs in one simulation, built and run by
// the first test that asks.
#include "model/units/trv_unit.h"

#include "tests/model/units/unit_bench.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <memory>

namespace rtsim::model {
namespace {

using namespace bench;

constexpr uint32_t kTarget = 2;   // the triangle the rays aim at
constexpr uint64_t kLatency = 8;  // the TRV pipeline (the paper's)
// A node that hits in L1: delivered, then the pipeline
constexpr uint64_t kStep = kL1Hit + kLatency;
constexpr uint64_t kStart0 = 10;    // trv0's first ray (cold)
constexpr uint64_t kBatch = 200;    // trv0: four identical rays at once (warm L1)
constexpr uint64_t kStart1 = 300;   // trv1's ray (cold L1, warm L2)
constexpr uint64_t kOutside = 400;  // trv0: a ray that misses the scene's box
constexpr int kBatchRays = 4;       // <= kStep: the rays never compete for an issue slot

struct TrvBench : Bench {
  TrvBench(sc_core::sc_module_name name, const MemoryImage& image, const AcceleratorConfig& c)
      : Bench(name, image, c),
        list0("list0", 64, nullptr),
        list1("list1", 64, nullptr),
        trv0("trv0", ctx, cfg.trv, 0),
        trv1("trv1", ctx, cfg.trv, 1) {
    attach(trv0.mem_side, kTrvStage, 0);
    attach(trv1.mem_side, kTrvStage, 1);
    trv0.to_list.bind(list0);
    trv1.to_list.bind(list1);
    trv0.to_shading.bind(done);
    trv1.to_shading.bind(done);
  }
  RayFifo list0, list1;
  TrvUnit trv0, trv1;
};

struct Scenario {
  Scene scene = row_of_triangles();
  KdTree tree = build_kdtree(scene.triangles);
  MemoryImage image{scene, tree};
  std::unique_ptr<TrvBench> b;
  uint32_t cold = 0, warm_l2 = 0, outside = 0;
  std::vector<uint32_t> batch;

  Scenario() {
    AcceleratorConfig c = config();
    c.trv.count = 2;
    b = std::make_unique<TrvBench>("bench", image, c);
    const float x = 4.f * kTarget;
    cold = b->add_ray(down_at(x));
    b->feed(&b->trv0.in, cold, kStart0);
    for (int k = 0; k < kBatchRays; ++k) {
      batch.push_back(b->add_ray(down_at(x)));
      b->feed(&b->trv0.in, batch.back(), kBatch);
    }
    outside = b->add_ray(down_at(100.f));
    b->feed(&b->trv0.in, outside, kOutside);
    warm_l2 = b->add_ray(down_at(x));
    b->feed(&b->trv1.in, warm_l2, kStart1);
    test::simulate();
    for (Unit* u : {static_cast<Unit*>(&b->trv0), static_cast<Unit*>(&b->trv1)})
      u->finish_accounting(at(kEndCycle));
    out0 = Bench::drain(b->list0);
    out1 = Bench::drain(b->list1);
    to_shading = Bench::drain(b->done);
  }
  // What left for LIST (from trv0, trv1) and for shading: (ray, cycle it was visible).
  std::vector<std::pair<uint32_t, uint64_t>> out0, out1, to_shading;
  // The nodes a ray aimed at the target fetches: the inner nodes above its leaf, and the leaf.
  std::vector<uint32_t> path() const {
    std::vector<uint32_t> p{0};
    const Vec3 target(4.f * kTarget, 0.f, -5.f);
    while (!tree.nodes[p.back()].is_leaf()) {
      const KdNode& n = tree.nodes[p.back()];
      p.push_back(target[n.axis()] < n.split() ? p.back() + 1 : n.above_child());
    }
    return p;
  }
  uint64_t nodes() const { return path().size(); }
  // Of those, the ones that are the first of their line (8 nodes a line, the section aligned):
  // the ray's first access to that line.
  uint64_t lines() const {
    uint64_t n = 0, last = ~uint64_t(0);
    for (uint32_t node : path()) n += node / 8 != last ? (last = node / 8, 1) : 0;
    return n;
  }
  // TRV's closed form for the walk: each node is delivered (`first` for a line's first node,
  // kL1Hit after), then the pipeline's 8 cycles.
  uint64_t walk(uint64_t first) const {
    return nodes() * kLatency + lines() * first + (nodes() - lines()) * kL1Hit;
  }
};

Scenario& run() {
  static Scenario r;
  return r;
}

TEST(TrvUnit, AColdRayReachesTheLeafOfItsTriangleOneNodePerStepAMissPerNewLine) {
  Scenario& r = run();
  ASSERT_GE(r.nodes(), 2u) << "the tree must have inner nodes for the walk to mean anything";
  const auto& out = r.out0;
  ASSERT_EQ(out.size(), 1u + kBatchRays);
  // A line's first node comes from memory (kMiss), every further node hits in L1.
  EXPECT_EQ(out[0].first, r.cold);
  EXPECT_EQ(out[0].second, kStart0 + r.walk(kMiss));
  // The right leaf: the one whose cell holds the triangle's centre, and it lists the triangle.
  const uint32_t leaf = r.b->pool[r.cold].trv.walk.leaf;
  EXPECT_EQ(leaf, locate_leaf(r.tree, Vec3(4.f * kTarget, 0.f, -5.f)));
  const KdLeaf& l = r.tree.leaves[leaf];
  EXPECT_NE(
      std::find(r.tree.prims.begin() + l.first, r.tree.prims.begin() + l.first + l.count, kTarget),
      r.tree.prims.begin() + l.first + l.count);
}

TEST(TrvUnit, RaysBackToBackIssueOnePerCycle) {
  Scenario& r = run();
  ASSERT_EQ(r.out0.size(), 1u + kBatchRays);
  const std::vector<std::pair<uint32_t, uint64_t>> batch(r.out0.begin() + 1, r.out0.end());
  // Ray k issues its first node at kBatch + k and every node after kStep: all hit in L1.
  for (int k = 0; k < kBatchRays; ++k) {
    EXPECT_EQ(batch[k].first, r.batch[k]);
    EXPECT_EQ(batch[k].second, kBatch + k + r.nodes() * kStep) << "ray " << k;
    EXPECT_EQ(r.b->pool[batch[k].first].trv.walk.leaf, r.b->pool[r.cold].trv.walk.leaf);
  }
}

TEST(TrvUnit, AnL1MissThatHitsTheSharedL2CostsBothHitLatencies) {
  Scenario& r = run();
  const auto& out = r.out1;
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].first, r.warm_l2);
  EXPECT_EQ(out[0].second, kStart1 + r.walk(kL1Hit + kL2Hit));
  EXPECT_EQ(r.b->trv1.l1().stats().misses, r.lines());
  EXPECT_EQ(r.b->trv1.l1().stats().hits, r.nodes() - r.lines());
  // One memory read per line in all: the L2 kept the lines trv0's first ray brought.
  EXPECT_EQ(r.b->memory.interconnect().port().stats().reads, r.lines());
  EXPECT_EQ(r.b->ram.reads, r.lines());
}

TEST(TrvUnit, ARayMissingTheSceneGoesToShadingAfterThePipelineWithoutAFetch) {
  Scenario& r = run();
  const auto& out = r.to_shading;
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].first, r.outside);
  EXPECT_EQ(out[0].second, kOutside + kLatency);
  EXPECT_FALSE(r.b->pool[r.outside].ist.result.found);
  EXPECT_EQ(r.b->trv0.stats().rays_started, 2u + kBatchRays);
  EXPECT_EQ(r.b->trv0.stats().rays_done, 1u);
  // trv0's L1: the cold ray's nodes (one miss) and the batch's (all hits); the outside ray none.
  EXPECT_EQ(r.b->trv0.l1().stats().accesses, (1 + kBatchRays) * r.nodes());
  EXPECT_EQ(r.b->trv0.l1().stats().misses, r.lines());
}

TEST(TrvUnit, BusyStalledAndIdleCyclesAddUpToTheElapsedCycles) {
  Scenario& r = run();
  const uint64_t n = r.nodes();
  // trv0: one operation per node, plus a re-issue per line the cold ray waited for, plus the
  // outside ray; idle only before its first ray (afterwards it owns rays: none retires here).
  const UnitStats& s0 = r.b->trv0.unit_stats();
  EXPECT_EQ(s0.busy_cycles, (n + r.lines()) + kBatchRays * n + 1);
  EXPECT_EQ(s0.idle_cycles, kStart0);
  EXPECT_EQ(s0.busy_cycles + s0.stalled_cycles + s0.idle_cycles, kEndCycle);
  const UnitStats& s1 = r.b->trv1.unit_stats();
  EXPECT_EQ(s1.busy_cycles, n);
  EXPECT_EQ(s1.idle_cycles, kStart1);
  EXPECT_EQ(s1.stalled_cycles, kEndCycle - kStart1 - n);
}

}  // namespace
}  // namespace rtsim::model
