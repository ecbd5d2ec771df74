// A record on two lines whose second line's allocation evicts the first (an IST L1 of one set and
// one way): the unit must test the triangle with the bytes the first line had when it was read,
// not with the L1's (it holds the second line by then) and without reading the first again.
// tests/model/units/unit_bench.h; one simulation for the file.
#include "model/units/ist_unit.h"
#include "model/units/lvb_updater.h"

#include "tests/model/units/unit_bench.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

namespace rtsim::model {
namespace {

using namespace bench;

constexpr uint32_t kLine = 256;

// Every line 256 bytes; the IST L1 and L2 hold one line each (one set, one way).
AcceleratorConfig one_line_l1() {
  AcceleratorConfig c = config();
  for (UnitTypeConfig* u : {&c.trv, &c.list, &c.ist, &c.shading}) {
    u->l1.line_bytes = kLine;
    u->l1.size_bytes = 64 * 1024;
    u->l2.line_bytes = kLine;
    u->l2.size_bytes = 256 * 1024;
  }
  c.ist.l1.size_bytes = kLine;
  c.ist.l1.ways = 1;
  c.ist.l2.size_bytes = kLine;  // nor does its L2 keep the first line: only the entry has it
  c.ist.l2.ways = 1;
  c.ist.l2.banks = 1;
  return c;
}

struct IstBench : Bench {
  IstBench(sc_core::sc_module_name name, const MemoryImage& image)
      : Bench(name, image, one_line_l1()), lvb("lvb_updater"), ist("ist0", ctx, cfg.ist) {
    attach(ist.mem_side, kIstStage, 0);
    ist.back.bind(*this);
    ist.to_shading.bind(done);
    ist.lvb.bind(lvb);
  }
  LvbUpdater lvb;
  IstUnit ist;
};

// 64 triangles across line boundaries, each at z = -(3 + k / 16) over the origin's ray.
Scene stack_of_triangles() {
  Scene s;
  s.add_material(Material{});
  for (int k = 0; k < 64; ++k) {
    const float z = -(3.f + float(k) / 16.f);
    s.triangles.push_back({Vec3(-1.f, -1.f, z), Vec3(1.f, -1.f, z), Vec3(0.f, 1.f, z), 0});
  }
  return s;
}

struct Scenario {
  Scene scene = stack_of_triangles();
  KdTree tree = build_kdtree(scene.triangles);
  MemoryImage image{scene, tree};
  std::unique_ptr<IstBench> b;
  uint32_t straddling = 0, before = 0;  // a triangle across a line boundary, one wholly before it
  uint32_t warm = 0, tested = 0;

  Scenario() {
    const uint32_t base = image.header().triangles.base;
    for (uint32_t k = 1; k < 64 && straddling == 0; ++k) {
      const uint32_t first = base + k * image::kTriangleBytes;
      if (first / kLine != (first + image::kTriangleBytes - 1) / kLine) straddling = k;
    }
    before = straddling - 1;
    b = std::make_unique<IstBench>("bench", image);
    warm = ray({before}, 10);         // brings the first line into the L1
    tested = ray({straddling}, 300);  // first line a hit, the second evicts it
    test::simulate();
  }
  uint32_t ray(std::vector<uint32_t> tris, uint64_t cycle) {
    const uint32_t id = b->add_ray({Vec3(0.f), Vec3(0.f, 0.f, -1.f)});
    RayState& r = b->pool[id];
    EXPECT_TRUE(
        traversal_begin(r.trv.walk, r.info.ray, false, image.header().bounds, b->ctx.abs_eps));
    r.trv.walk.leaf = 0;
    r.list.tris = std::move(tris);
    b->feed(&b->ist.in, id, cycle);
    return id;
  }
};

TEST(TwoLineRecords, ARecordWhoseSecondLineEvictsItsFirstIsTestedWithTheFirstLinesBytes) {
  Scenario r;
  ASSERT_GT(r.straddling, 0u);
  const TraversalResult& hit = r.b->pool[r.tested].ist.result;
  ASSERT_TRUE(hit.found);
  EXPECT_EQ(hit.hit.tri, r.straddling);
  EXPECT_EQ(hit.hit.t, 3.f + float(r.straddling) / 16.f);
  const CacheStats& l1 = r.b->ist.l1().stats();
  // Warm ray: one miss. Tested ray: the first line hits, the second misses and evicts it; the
  // first is not read again.
  EXPECT_EQ(l1.hits, 1u);
  EXPECT_EQ(l1.misses, 2u);
  EXPECT_EQ(l1.evictions, 1u);
  EXPECT_FALSE(r.b->ist.l1().contains(
      (r.image.header().triangles.base + r.straddling * image::kTriangleBytes) / kLine * kLine));
}

}  // namespace
}  // namespace rtsim::model
