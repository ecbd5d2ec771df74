// The IST unit on its own (tests/model/units/unit_bench.h): one ray-triangle test per operation
// (36-cycle pipeline) over the triangles LIST gave the ray, the closest hit kept with the tie
// and window rules, the LVB updater called on every closest-hit update (and never for a shadow
// ray), and the ray sent on when its leaf's last test completes: to shading when its traversal is
// over, back to its TRV unit otherwise. Timing: a test issued at c on a triangle delivered at d
// completes at max(c, d) + 36; a 48-byte triangle may straddle two lines and is ready when both
// are (docs/model-design.md). One simulation for the file, built by the first test.
#include "model/units/ist_unit.h"
#include "model/units/lvb_updater.h"

#include "tests/model/units/unit_bench.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <memory>

namespace rtsim::model {
namespace {

using namespace bench;

// Triangle 0 far (z = -5) and triangle 1 near (z = -3), both over the origin's ray down -z;
// triangle 2 off to the side. Triangle k's 48 bytes start at 48 k: triangle 0 is in line 0,
// triangle 1 straddles lines 0 and 1.
Scene far_and_near() {
  Scene s;
  s.add_material(Material{});
  s.triangles.push_back({Vec3(-1.f, -1.f, -5.f), Vec3(1.f, -1.f, -5.f), Vec3(0.f, 1.f, -5.f), 0});
  s.triangles.push_back({Vec3(-1.f, -1.f, -3.f), Vec3(1.f, -1.f, -3.f), Vec3(0.f, 1.f, -3.f), 0});
  s.triangles.push_back({Vec3(9.f, -1.f, -5.f), Vec3(11.f, -1.f, -5.f), Vec3(10.f, 1.f, -5.f), 0});
  return s;
}

constexpr uint64_t kLatency = 36;  // the IST pipeline (the paper's)
// The scenarios' start cycles, far enough apart not to meet.
constexpr uint64_t kA = 10, kB = 300, kC = 600, kD = 900, kE = 1200;

struct IstBench : Bench {
  IstBench(sc_core::sc_module_name name, const MemoryImage& image)
      : Bench(name, image, config()), lvb("lvb_updater"), ist("ist0", ctx, cfg.ist) {
    attach(ist.mem_side, kIstStage, 0);
    ist.back.bind(*this);
    ist.to_shading.bind(done);
    ist.lvb.bind(lvb);
  }
  LvbUpdater lvb;
  IstUnit ist;
};

struct Scenario {
  Scene scene = far_and_near();
  KdTree tree = build_kdtree(scene.triangles);
  MemoryImage image{scene, tree};
  std::unique_ptr<IstBench> b;
  uint32_t a = 0, bb = 0, c = 0, d = 0, e = 0;
  std::vector<std::pair<uint32_t, uint64_t>> to_shading;

  // A ray down -z from (x, 0, 0) at a leaf (number `leaf`, LVB word `lvb`) listing `tris`, as
  // LIST hands it over.
  uint32_t ray(float x, std::vector<uint32_t> tris, uint32_t lvb, uint64_t cycle,
               RayType type = RayType::kPrimary) {
    const uint32_t id = b->add_ray({Vec3(x, 0.f, 0.f), Vec3(0.f, 0.f, -1.f)}, type);
    RayState& r = b->pool[id];
    EXPECT_TRUE(traversal_begin(r.trv.walk, r.info.ray, type == RayType::kShadow,
                                image.header().bounds, b->ctx.abs_eps));
    r.trv.walk.leaf = 7;
    r.list.leaf_lvb = lvb;
    r.list.tris = std::move(tris);
    b->feed(&b->ist.in, id, cycle);
    return id;
  }

  Scenario() {
    b = std::make_unique<IstBench>("bench", image);
    a = ray(0.f, {0}, 0x1, kA);                    // cold: triangle 0's line from memory
    bb = ray(0.f, {0, 1}, 0x2, kB);                // far then near: line 1 is cold
    c = ray(0.f, {1, 0}, 0x4, kC);                 // near then far: all warm
    d = ray(0.f, {0}, 0x8, kD, RayType::kShadow);  // any hit: no LVB update
    e = ray(5.f, {0}, 0x10, kE);                   // misses; a cell is still on its stack
    TraversalState& we = b->pool[e].trv.walk;
    we.stack[we.sp++] = {0, we.tmin, we.tmax};
    test::simulate();
    b->ist.finish_accounting(at(kEndCycle));
    to_shading = Bench::drain(b->done);
  }
};

Scenario& run() {
  static Scenario r;
  return r;
}

TEST(IstUnit, KeepsTheClosestHitAndSendsTheRayToShadingWhenTheLastTestCompletes) {
  Scenario& r = run();
  ASSERT_EQ(r.to_shading.size(), 4u);
  // A: triangle 0 is cold: delivered kMiss after issue, then the pipeline.
  EXPECT_EQ(r.to_shading[0], std::make_pair(r.a, kA + kMiss + kLatency));
  // B: triangle 0 hits in L1 at kB; triangle 1 issues at kB + 1 and waits for its second line,
  // a cold one; the leaf is done when that test completes.
  EXPECT_EQ(r.to_shading[1], std::make_pair(r.bb, kB + 1 + kMiss + kLatency));
  // C: two warm tests, one per cycle: the last completes at kC + 1 + kL1Hit + 36.
  EXPECT_EQ(r.to_shading[2], std::make_pair(r.c, kC + 1 + kL1Hit + kLatency));
  // D: a shadow ray stops after the leaf with its hit.
  EXPECT_EQ(r.to_shading[3], std::make_pair(r.d, kD + kL1Hit + kLatency));

  const RayState &a = r.b->pool[r.a], &b = r.b->pool[r.bb], &c = r.b->pool[r.c],
                 &d = r.b->pool[r.d];
  EXPECT_EQ(a.ist.result.hit.tri, 0u);
  EXPECT_EQ(a.ist.result.hit.t, 5.f);
  for (const RayState* s : {&b, &c}) {  // the near one, whatever the order of the tests
    EXPECT_EQ(s->ist.result.hit.tri, 1u);
    EXPECT_EQ(s->ist.result.hit.t, 3.f);
    EXPECT_EQ(s->ist.result.hit.leaf, 7u);
  }
  EXPECT_TRUE(d.ist.result.found);
  EXPECT_EQ(r.b->ist.stats().tests, 7u);  // A 1, B 2, C 2, D 1, E 1
  EXPECT_EQ(r.b->ist.stats().hits, 6u);   // every test but E's
}

TEST(IstUnit, CallsTheLvbUpdaterOnEveryClosestHitUpdateOfANonShadowRay) {
  Scenario& r = run();
  // A: one update; B: the far hit, then the nearer one; C: the near hit only (the far one is
  // not closer); D: a shadow ray, none; E: no hit.
  StatsRegistry reg;
  r.b->lvb.register_stats(reg, "lvb");
  EXPECT_EQ(reg.value("lvb.updates"), 1.0 + 2.0 + 1.0);
  EXPECT_EQ(r.b->pool[r.a].ist.lvb, 0x1u);
  EXPECT_EQ(r.b->pool[r.bb].ist.lvb, 0x2u);
  EXPECT_EQ(r.b->pool[r.c].ist.lvb, 0x4u);
  EXPECT_EQ(r.b->pool[r.d].ist.lvb, 0u);
  EXPECT_EQ(r.b->pool[r.e].ist.lvb, 0u);
}

TEST(IstUnit, ARayWithCellsLeftGoesBackToItsTrvUnitWhenItsLeafIsDone) {
  Scenario& r = run();
  ASSERT_EQ(r.b->returned.size(), 1u);
  EXPECT_EQ(r.b->returned[0].first, r.e);
  EXPECT_EQ(cycle_of(r.b->returned[0].second), kE + kL1Hit + kLatency);
  EXPECT_FALSE(r.b->pool[r.e].ist.result.found);
  EXPECT_EQ(r.b->pool[r.e].trv.walk.node, 0u);  // the cell popped from its stack
}

TEST(IstUnit, BusyStalledAndIdleCyclesAddUpToTheElapsedCycles) {
  Scenario& r = run();
  const UnitStats& s = r.b->ist.unit_stats();
  // Operations: A 2 (a miss, then the re-issue), B 3 (one more for the straddling triangle's
  // miss), C 2, D 1, E 1. The unit holds a ray from its first operation to its last.
  EXPECT_EQ(s.busy_cycles, 9u);
  const uint64_t held = (kMiss + 1) + (1 + kMiss + 1) + 2 + 1 + 1;
  EXPECT_EQ(s.stalled_cycles, held - s.busy_cycles);
  EXPECT_EQ(s.idle_cycles, kEndCycle - held);
  EXPECT_EQ(s.busy_cycles + s.stalled_cycles + s.idle_cycles, kEndCycle);
}

}  // namespace
}  // namespace rtsim::model
