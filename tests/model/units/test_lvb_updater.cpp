// The LVB updater (the paper's Fig. 5): whenever IST updates a ray's closest hit, the ray takes
// the LVB word of the leaf being tested, so a finished ray carries the word of the leaf that holds
// its hit. Checked on its own, and in a real TRV -> LIST -> IST chain
// (tests/model/units/unit_bench.h; the bench hands rays IST returns back to TRV, as the accelerator
// does) over a small kd-tree whose leaves carry distinct words in the memory image: LIST reads the
// word from the fetched leaf record, and each hit ray ends with its hit leaf's word. The updater
// has no timing of its own (two registers and a mux): the chain's cold ray leaves IST at the sum of
// the three units' closed forms, with nothing added for the update.
#include "model/units/ist_unit.h"
#include "model/units/list_unit.h"
#include "model/units/lvb_updater.h"
#include "model/units/trv_unit.h"

#include "tests/model/units/unit_bench.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <memory>

namespace rtsim::model {
namespace {

using namespace bench;

uint32_t word_of(uint32_t leaf) { return 0x100u | leaf; }  // distinct per leaf, never all ones

constexpr uint64_t kStart = 10;    // the first ray: everything cold
constexpr uint64_t kOthers = 500;  // the rest, once the first is through

struct ChainBench : Bench {
  ChainBench(sc_core::sc_module_name name, const MemoryImage& image)
      : Bench(name, image, config()),
        lvb("lvb_updater"),
        ist("ist0", ctx, cfg.ist),
        list("list0", ctx, cfg.list),
        trv("trv0", ctx, cfg.trv, 0) {
    attach(ist.mem_side, kIstStage, 0);
    attach(list.mem_side, kListStage, 0);
    attach(trv.mem_side, kTrvStage, 0);
    trv.to_list.bind(list.in);
    trv.to_shading.bind(done);
    list.to_ist.bind(ist.in);
    ist.back.bind(*this);
    ist.to_shading.bind(done);
    ist.lvb.bind(lvb);
  }
  // The ray goes back to its TRV unit, as through the router.
  bool leaf_done(uint32_t ray, Tick when) override { return trv.leaf_done(ray, when); }
  LvbUpdater lvb;
  IstUnit ist;
  ListUnit list;
  TrvUnit trv;
};

struct Scenario {
  Scene scene = row_of_triangles();
  KdTree tree = build_kdtree(scene.triangles);
  MemoryImage image = with_words();
  std::unique_ptr<ChainBench> b;
  std::vector<uint32_t> aimed;  // ray k aims at triangle k
  uint32_t between = 0, shadow = 0;
  std::vector<std::pair<uint32_t, uint64_t>> out;

  MemoryImage with_words() {
    MemoryImage m(scene, tree);
    for (uint32_t l = 0; l < tree.leaves.size(); ++l) m.set_leaf_lvb(l, word_of(l));
    return m;
  }

  Scenario() {
    b = std::make_unique<ChainBench>("bench", image);
    for (uint32_t k = 0; k < 4; ++k) {
      aimed.push_back(b->add_ray(down_at(4.f * k)));
      b->feed(&b->trv.in, aimed.back(), k == 0 ? kStart : kOthers);
    }
    between = b->add_ray(down_at(2.f));  // between two triangles: no hit
    b->feed(&b->trv.in, between, kOthers);
    shadow = b->add_ray(down_at(4.f), RayType::kShadow);  // hits triangle 1, takes no word
    b->feed(&b->trv.in, shadow, kOthers);
    test::simulate();
    out = Bench::drain(b->done);
  }
};

Scenario& run() {
  static Scenario r;
  return r;
}

TEST(LvbUpdater, TakesTheLeafWordOnEachUpdateAndCountsIt) {
  LvbUpdater u("lone_updater");
  EXPECT_EQ(u.closest_hit(0x5), 0x5u);
  // A closer hit in another leaf replaces the word, it does not merge.
  EXPECT_EQ(u.closest_hit(0x2), 0x2u);
  StatsRegistry reg;
  u.register_stats(reg, "u");
  EXPECT_EQ(reg.value("u.updates"), 2.0);
}

TEST(LvbUpdater, EachHitRayEndsWithTheWordOfTheLeafHoldingItsHit) {
  Scenario& r = run();
  ASSERT_EQ(r.out.size(), 6u);
  for (uint32_t k = 0; k < 4; ++k) {
    const RayState& s = r.b->pool[r.aimed[k]];
    ASSERT_TRUE(s.ist.result.found) << "ray " << k;
    EXPECT_EQ(s.ist.result.hit.tri, k);
    EXPECT_EQ(s.ist.result.hit.leaf, locate_leaf(r.tree, Vec3(4.f * k, 0.f, -5.f)));
    EXPECT_EQ(s.ist.lvb, word_of(s.ist.result.hit.leaf)) << "ray " << k;
  }
  EXPECT_FALSE(r.b->pool[r.between].ist.result.found);
  EXPECT_EQ(r.b->pool[r.between].ist.lvb, 0u);
  EXPECT_TRUE(r.b->pool[r.shadow].ist.result.found);
  EXPECT_EQ(r.b->pool[r.shadow].ist.lvb, 0u);
  // One update per hit primary ray: the triangles do not overlap, so no ray finds a closer one.
  StatsRegistry reg;
  r.b->lvb.register_stats(reg, "lvb");
  EXPECT_EQ(reg.value("lvb.updates"), 4.0);
}

TEST(LvbUpdater, TheUpdateAddsNoCycle) {
  Scenario& r = run();
  // Ray 0, everything cold. TRV: each node on its path is delivered (kMiss for the first node
  // of a line, 8 nodes a line; kL1Hit after), then 8 cycles; LIST: two cold lines, the leaf
  // record and the list; IST: one cold triangle (triangle 0, in the section's first line; the
  // closed form assumes ray 0's leaf holds it alone).
  std::vector<uint32_t> path{0};
  while (!r.tree.nodes[path.back()].is_leaf()) {
    const KdNode& n = r.tree.nodes[path.back()];
    path.push_back(Vec3(0.f, 0.f, -5.f)[n.axis()] < n.split() ? path.back() + 1 : n.above_child());
  }
  const uint32_t leaf = r.tree.nodes[path.back()].leaf_index();
  ASSERT_EQ(r.tree.leaves[leaf].count, 1u)
      << "the closed form assumes one triangle in ray 0's leaf";
  uint64_t trv = 0, line = ~uint64_t(0);
  for (uint32_t node : path) {
    trv += 8 + (node / 8 != line ? kMiss : kL1Hit);
    line = node / 8;
  }
  const uint64_t list = 2 * (kMiss + 2);
  const uint64_t ist = kMiss + 36;
  ASSERT_FALSE(r.out.empty());
  EXPECT_EQ(r.out[0], std::make_pair(r.aimed[0], kStart + trv + list + ist));
}

}  // namespace
}  // namespace rtsim::model
