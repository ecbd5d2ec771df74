// The BVH traversal unit on its own (tests/model/units/unit_bench.h) on trees of one node: bvh4
// roots whose children are all leaves (max_leaf_size 1), a 128-byte node on exactly two L1 lines.
// The documented rules (model/units/bvh_unit.h): an operation issues per cycle, reads the node's
// two lines and tests box_tests_per_cycle boxes, and a visit is done `latency` (L) cycles after
// its last operation and its data: done_at = max(node ready, last operation's issue) + L. So
//   a cold ray          leaves for LIST at start + kMiss + L (both lines missed together; the
//                       re-issued operation reads them as they arrive)
//   a warm ray          start + kL1Hit + L
//   P operations        start + max(kL1Hit, P - 1) + L warm, start + kMiss + P - 1 + L cold
//                       (P = ceil(4 / box_tests_per_cycle))
//   off the root box    to shading at start + L, no node read
// A node with one hit child pushes nothing: the child goes straight to LIST. With more, the rest
// go on the ray's stack; the unit's leaf_done pops one and the ray is at LIST again one operation
// (1 cycle) after it comes back, plus spill_latency when the entry had spilled off chip; with the
// stack empty (or the rest beyond the hit found) leaf_done ends the traversal (false). A stand-in
// for LIST and IST hands each leaf back kLeafWork cycles after it shows. SystemC elaborates once
// per process: every scenario runs in one simulation, built and run by the first test that asks.
#include "model/units/bvh_unit.h"

#include "tests/model/units/unit_bench.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <tuple>

namespace rtsim::model {
namespace {

using namespace bench;

constexpr uint64_t kLatency = 8;    // the box pipeline (cfg.bvh.latency)
constexpr uint64_t kLeafWork = 12;  // LIST and IST on a leaf (the stand-in's)
constexpr uint64_t kSpill = 7;      // a refill of spilled stack entries
constexpr uint32_t kTarget = 2;     // the triangle the cold row rays aim at
constexpr uint64_t kCold = 10;      // each bench's first ray
constexpr uint64_t kWarm = 100;     // later rays, kGap apart: none waits for another
constexpr uint64_t kGap = 20;
constexpr uint64_t kOutside = 300;  // a ray beside the scene
constexpr uint32_t kNoRay = ~0u;

// n triangles stacked under x = 0, at z = -5, -6, ...: a ray down at x = 0 hits every leaf box.
Scene stacked(int n) {
  Scene s;
  s.add_material(Material{});
  for (int i = 0; i < n; ++i) {
    const float z = -5.f - float(i);
    s.triangles.push_back({Vec3(-1.f, -1.f, z), Vec3(1.f, -1.f, z), Vec3(0.f, 1.f, z), 0});
  }
  return s;
}

Bvh bvh4(const Scene& s) {
  BvhConfig c;
  c.branching = 4;
  c.max_leaf_size = 1;
  return build_bvh(s.triangles, c);
}

// The tree is one root whose `n` children are leaves of one triangle each.
bool one_node(const Bvh& b, uint32_t n) {
  if (b.nodes.size() != 1 || b.nodes[0].child_count != n) return false;
  return std::all_of(b.nodes[0].children, b.nodes[0].children + n,
                     [](const BvhChild& c) { return c.count == 1; });
}

// The leaf that lists triangle `tri`.
uint32_t leaf_of(const Bvh& b, uint32_t tri) {
  for (uint32_t l = 0; l < b.leaves.size(); ++l)
    if (std::count(b.prims.begin() + b.leaves[l].first,
                   b.prims.begin() + b.leaves[l].first + b.leaves[l].count, tri))
      return l;
  return kNoRay;
}

// config() with the BVH units in TRV's place, set up as config() sets TRV (one unit, round
// latencies, no ports, ideal links).
AcceleratorConfig bvh_config() {
  AcceleratorConfig c = config();
  c.structure = Structure::kBvh;
  c.bvh = c.trv;
  c.bvh.latency = uint32_t(kLatency);
  return c;
}

// One BVH unit; the bench is LIST and IST (a sink for the unit's to_list) and the router (its
// leaf_done passes to the unit's, as the router passes it to a ray's owner).
struct BvhBench : Bench, RaySink {
  BvhBench(sc_core::sc_module_name name, const MemoryImage& image, const BvhWalkConfig& walk)
      : Bench(name, image, bvh_config()), unit("bvh0", ctx, cfg.bvh, walk, 0) {
    ctx.bvh = true;
    ctx.bvh_format = bvh_formats().find(ctx.header.accel);  // as the accelerator's begin_frame
    attach(unit.mem_side, kTrvStage, 0);
    unit.to_list.bind(static_cast<RaySink&>(*this));
    unit.to_shading.bind(done);
  }
  // A leaf for LIST: recorded as (ray, cycle it shows, leaf); back kLeafWork cycles later. The
  // ray `hit_ray`'s tests find the nearest triangle (t = 5).
  bool push(uint32_t ray, Tick ready, Tick) override {
    RayState& r = pool[ray];
    lists.emplace_back(ray, cycle_of(ready), r.trv.bvh.leaf);
    if (ray == hit_ray) {
      r.ist.result.found = true;
      r.ist.result.best = 5.f;
    }
    leaf_done(ray, ready + at(kLeafWork));
    return true;
  }
  void add_producer(Unit*) override {}
  bool leaf_done(uint32_t ray, Tick when) override {
    const bool goes_on = unit.leaf_done(ray, when);
    backs.emplace_back(ray, cycle_of(when), goes_on);
    return goes_on;
  }
  BvhUnit unit;
  uint32_t hit_ray = kNoRay;
  std::vector<std::tuple<uint32_t, uint64_t, uint32_t>> lists;  // (ray, cycle, leaf)
  std::vector<std::tuple<uint32_t, uint64_t, bool>> backs;      // (ray, cycle, goes on)
};

struct Scenario {
  Scene row = row_of_triangles(), pair = stacked(2), triple = stacked(3);
  Bvh row_bvh = bvh4(row), pair_bvh = bvh4(pair), triple_bvh = bvh4(triple);
  MemoryImage row_image{row, row_bvh, parse_accel("bvh4")},
      pair_image{pair, pair_bvh, parse_accel("bvh4")},
      triple_image{triple, triple_bvh, parse_accel("bvh4")};
  // wide: 4 boxes an operation (the default); narrow: 2; two: the pair; spill: the triple with
  // one stack entry on chip.
  std::unique_ptr<BvhBench> wide, narrow, two, spill;
  uint32_t cold = 0, outside = 0, narrow_cold = 0, narrow_warm = 0, no_hit = 0, hit = 0, deep = 0;
  std::vector<uint32_t> warm;
  std::vector<std::pair<uint32_t, uint64_t>> to_shading;

  Scenario() {
    BvhWalkConfig w;
    wide = std::make_unique<BvhBench>("wide", row_image, w);
    w.box_tests_per_cycle = 2;
    narrow = std::make_unique<BvhBench>("narrow", row_image, w);
    two = std::make_unique<BvhBench>("two", pair_image, BvhWalkConfig{});
    w = BvhWalkConfig{};
    w.stack_entries = 1;
    w.spill_latency = uint32_t(kSpill);
    spill = std::make_unique<BvhBench>("spill", triple_image, w);
    auto ray = [](BvhBench& b, float x, uint64_t cycle) {
      const uint32_t id = b.add_ray(down_at(x));
      b.feed(&b.unit.in, id, cycle);
      return id;
    };
    cold = ray(*wide, 4.f * kTarget, kCold);
    for (uint32_t k = 0; k < 4; ++k) warm.push_back(ray(*wide, 4.f * k, kWarm + k * kGap));
    outside = ray(*wide, 100.f, kOutside);
    narrow_cold = ray(*narrow, 4.f * kTarget, kCold);
    narrow_warm = ray(*narrow, 4.f * kTarget, kWarm);
    no_hit = ray(*two, 0.f, kCold);
    hit = two->hit_ray = ray(*two, 0.f, kWarm);
    deep = ray(*spill, 0.f, kCold);
    test::simulate();
    for (BvhBench* b : benches()) b->unit.finish_accounting(at(kEndCycle));
    to_shading = Bench::drain(wide->done);
  }
  std::vector<BvhBench*> benches() const {
    return {wide.get(), narrow.get(), two.get(), spill.get()};
  }
};

Scenario& run() {
  static Scenario r;
  return r;
}

TEST(BvhUnit, EachTreeIsOneNodeOfLeavesOnTwoL1Lines) {
  Scenario& r = run();
  ASSERT_TRUE(one_node(r.row_bvh, 4));
  ASSERT_TRUE(one_node(r.pair_bvh, 2));
  ASSERT_TRUE(one_node(r.triple_bvh, 3));
  const uint32_t line = r.wide->unit.l1().line_bytes();
  EXPECT_EQ(r.row_image.header().node_bytes(), 2 * line);
  EXPECT_EQ(r.row_image.header().nodes.base % line, 0u);
}

TEST(BvhUnit, AColdRayMissesBothLinesTogetherAndReachesItsTrianglesLeaf) {
  Scenario& r = run();
  ASSERT_TRUE(one_node(r.row_bvh, 4));
  ASSERT_EQ(r.wide->lists.size(), 5u);
  EXPECT_EQ(r.wide->lists[0],
            std::make_tuple(r.cold, kCold + kMiss + kLatency, leaf_of(r.row_bvh, kTarget)));
  // One memory read per line, both at once: the node is there when the later line is.
  EXPECT_EQ(r.wide->unit.l1().stats().misses, 2u);
  EXPECT_EQ(r.wide->ram.reads, 2u);
}

TEST(BvhUnit, WarmRaysTakeAnL1HitAndThePipeline) {
  Scenario& r = run();
  ASSERT_TRUE(one_node(r.row_bvh, 4));
  ASSERT_EQ(r.wide->lists.size(), 5u);
  for (uint32_t k = 0; k < 4; ++k)
    EXPECT_EQ(r.wide->lists[1 + k], std::make_tuple(r.warm[k], kWarm + k * kGap + kL1Hit + kLatency,
                                                    leaf_of(r.row_bvh, k)))
        << "ray " << k;
  EXPECT_EQ(r.wide->unit.l1().stats().hits, 2u * 4);  // both lines, each warm ray
}

TEST(BvhUnit, TwoBoxesAnOperationTakeASecondOperation) {
  Scenario& r = run();
  const auto& out = r.narrow->lists;
  ASSERT_EQ(out.size(), 2u);
  const uint64_t ops = 2;  // 4 boxes, 2 an operation
  // Cold: the second operation issues the cycle after the re-issued first, data in hand.
  EXPECT_EQ(out[0], std::make_tuple(r.narrow_cold, kCold + kMiss + (ops - 1) + kLatency,
                                    leaf_of(r.row_bvh, kTarget)));
  // Warm: the second operation issues as the L1 delivers (kL1Hit = 1): it costs nothing here.
  EXPECT_EQ(out[1], std::make_tuple(r.narrow_warm, kWarm + std::max(kL1Hit, ops - 1) + kLatency,
                                    leaf_of(r.row_bvh, kTarget)));
  const BvhStats& s = r.narrow->unit.stats();
  EXPECT_EQ(s.node_fetches, 2u);
  EXPECT_EQ(s.node_operations, 2u * ops);
  EXPECT_EQ(s.box_tests, 2u * 4);
}

TEST(BvhUnit, ARayBesideTheRootBoxGoesToShadingAfterThePipelineWithoutAFetch) {
  Scenario& r = run();
  ASSERT_EQ(r.to_shading.size(), 1u);
  EXPECT_EQ(r.to_shading[0], std::make_pair(r.outside, kOutside + kLatency));
  EXPECT_FALSE(r.wide->pool[r.outside].ist.result.found);
  EXPECT_EQ(r.wide->unit.l1().stats().accesses, 2u * 5);  // the other five rays' two lines
}

TEST(BvhUnit, AfterItsOnlyLeafLeafDoneEndsTheRaysTraversal) {
  Scenario& r = run();
  ASSERT_EQ(r.wide->backs.size(), 5u);
  for (const auto& [ray, cycle, goes_on] : r.wide->backs) EXPECT_FALSE(goes_on) << "ray " << ray;
  EXPECT_EQ(r.wide->backs[0], std::make_tuple(r.cold, kCold + kMiss + kLatency + kLeafWork, false));
}

TEST(BvhUnit, StatsCountTheVisitsAndTheCyclesAddUp) {
  Scenario& r = run();
  const BvhStats& s = r.wide->unit.stats();
  EXPECT_EQ(s.node_fetches, 5u);
  EXPECT_EQ(s.node_operations, 5u);
  EXPECT_EQ(s.box_tests, 5u * 4);
  EXPECT_EQ(s.leaves, 5u);
  EXPECT_EQ(s.rays_started, 6u);
  EXPECT_EQ(s.rays_done, 1u);     // the outside ray; the others' end in leaf_done
  EXPECT_EQ(s.stack_pushes, 0u);  // one hit child: it goes straight on
  EXPECT_EQ(s.stack_pops, 0u);
  // Busy: an operation per node, plus the cold ray's parked first issue, plus the outside ray;
  // narrow: two operations per node plus the parked one; two and spill: the leaf_next reads.
  // Idle only before the first ray: the rays keep their slots (nothing releases them here).
  const uint64_t busy[] = {5 + 1 + 1, 4 + 1, 3 + 1, 2 + 2};
  for (size_t i = 0; i < 4; ++i) {
    const UnitStats& u = r.benches()[i]->unit.unit_stats();
    EXPECT_EQ(u.busy_cycles, busy[i]) << "bench " << i;
    EXPECT_EQ(u.idle_cycles, kCold) << "bench " << i;
    EXPECT_EQ(u.busy_cycles + u.stalled_cycles + u.idle_cycles, kEndCycle) << "bench " << i;
  }
}

TEST(BvhUnit, TheFartherHitChildWaitsOnTheStackForTheNextLeafOperation) {
  Scenario& r = run();
  ASSERT_TRUE(one_node(r.pair_bvh, 2));
  const uint32_t near = leaf_of(r.pair_bvh, 0), far = leaf_of(r.pair_bvh, 1);
  const auto& out = r.two->lists;
  ASSERT_EQ(out.size(), 3u);
  const uint64_t first = kCold + kMiss + kLatency, back = first + kLeafWork;
  EXPECT_EQ(out[0], std::make_tuple(r.no_hit, first, near));
  EXPECT_EQ(out[1], std::make_tuple(r.no_hit, back + 1, far));  // one operation to pop
  EXPECT_EQ(out[2], std::make_tuple(r.hit, kWarm + kL1Hit + kLatency, near));
  ASSERT_EQ(r.two->backs.size(), 3u);
  EXPECT_EQ(r.two->backs[0], std::make_tuple(r.no_hit, back, true));
  EXPECT_EQ(r.two->backs[1], std::make_tuple(r.no_hit, back + 1 + kLeafWork, false));
  // A hit at t = 5 leaves the leaf at t = 6 beyond reach: skipped, and the traversal is over.
  EXPECT_EQ(r.two->backs[2], std::make_tuple(r.hit, kWarm + kL1Hit + kLatency + kLeafWork, false));
  const BvhStats& s = r.two->unit.stats();
  EXPECT_EQ(s.stack_pushes, 2u);  // one a ray
  EXPECT_EQ(s.stack_pops, 2u);    // no_hit's far leaf, and the one hit skips
  EXPECT_EQ(s.leaves, 3u);
  EXPECT_EQ(s.box_tests, 2u * 2);
  EXPECT_EQ(s.stack_spills, 0u);
  EXPECT_EQ(s.stack_refills, 0u);
}

TEST(BvhUnit, AnEntrySpilledOffChipComesBackAfterTheSpillLatency) {
  Scenario& r = run();
  ASSERT_TRUE(one_node(r.triple_bvh, 3));
  const auto& out = r.spill->lists;
  ASSERT_EQ(out.size(), 3u);
  // Two entries pushed, one on chip: the farthest spills; the second pop refills it.
  const uint64_t first = kCold + kMiss + kLatency, second = first + kLeafWork + 1;
  EXPECT_EQ(out[0], std::make_tuple(r.deep, first, leaf_of(r.triple_bvh, 0)));
  EXPECT_EQ(out[1], std::make_tuple(r.deep, second, leaf_of(r.triple_bvh, 1)));
  EXPECT_EQ(out[2],
            std::make_tuple(r.deep, second + kLeafWork + kSpill + 1, leaf_of(r.triple_bvh, 2)));
  ASSERT_EQ(r.spill->backs.size(), 3u);
  EXPECT_FALSE(std::get<2>(r.spill->backs[2]));
  const BvhStats& s = r.spill->unit.stats();
  EXPECT_EQ(s.stack_pushes, 2u);
  EXPECT_EQ(s.stack_spills, 1u);
  EXPECT_EQ(s.stack_refills, 1u);
  EXPECT_EQ(s.stack_pops, 2u);
}

}  // namespace
}  // namespace rtsim::model
