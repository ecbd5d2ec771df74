// A unit needs no memory system: a TRV unit whose mem_side is bound to a scripted level (a
// LineSource that hands out the image's bytes after a fixed latency) walks a ray to its leaf in
// the closed form of the documented rules: per node, its delivery (a line's first node: the L1's
// tag check plus the level's latency; the rest hit in L1) and then the pipeline's 8 cycles. The
// level sees one request per line, asked for right after the L1's tag check.
#include "kernels/kdtree.h"
#include "kernels/memory_image.h"
#include "model/accelerator_config.h"
#include "model/sim/calendar.h"
#include "model/units/trv_unit.h"
#include "tests/model/units/unit_bench.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <memory>
#include <vector>

namespace rtsim::model {
namespace {

using bench::at;
using bench::cycle_of;

constexpr uint64_t kL1Hit = 1, kLevel = 13, kLatency = 8;  // distinct, so a mix-up shows
constexpr uint64_t kStart = 10;

// Every line `kLevel` cycles after it is asked for, with the image's bytes.
class ScriptedLevel : public sc_core::sc_object, public LineSource {
 public:
  ScriptedLevel(const char* name, const std::vector<uint8_t>& bytes)
      : sc_core::sc_object(name), bytes_(bytes) {}
  Tick fetch_line(uint64_t line, Tick now, FillListener*, uint64_t) override {
    asked.push_back({line, now});
    return now + at(kLevel);
  }
  const uint8_t* line_data(uint64_t line) const override { return bytes_.data() + line; }
  uint32_t line_bytes() const override { return 64; }
  std::vector<std::pair<uint64_t, Tick>> asked;

 private:
  const std::vector<uint8_t>& bytes_;
};

struct LoneTrv : sc_core::sc_module {
  LoneTrv(sc_core::sc_module_name name, const MemoryImage& image, const UnitTypeConfig& cfg)
      : sc_core::sc_module(name),
        calendar("calendar"),
        pool(8),
        padded(padded_bytes(image)),
        level("level", padded),
        to_list("to_list", 8, nullptr),
        to_shading("to_shading", 8, nullptr),
        trv("trv0", context(image), cfg, 0) {
    trv.mem_side.bind(level);
    trv.to_list.bind(to_list);
    trv.to_shading.bind(to_shading);
  }
  const ModelContext& context(const MemoryImage& image) {
    ctx.calendar = &calendar;
    ctx.pool = &pool;
    ctx.header = image.header();
    ctx.clock = Clock();
    ctx.abs_eps = 1e-6f * ctx.header.bounds.diagonal();
    return ctx;
  }
  // Whole lines, so the last node's line can be read.
  static std::vector<uint8_t> padded_bytes(const MemoryImage& image) {
    std::vector<uint8_t> b(image.bytes());
    b.resize((b.size() + 63) / 64 * 64, 0);
    return b;
  }
  Calendar calendar;
  RayPool pool;
  ModelContext ctx;
  std::vector<uint8_t> padded;
  ScriptedLevel level;
  RayFifo to_list, to_shading;
  TrvUnit trv;
};

struct Scenario {
  Scene scene = bench::row_of_triangles();
  KdTree tree = build_kdtree(scene.triangles);
  MemoryImage image{scene, tree};
  std::unique_ptr<LoneTrv> b;
  uint32_t ray = 0;
  std::vector<std::pair<uint32_t, uint64_t>> out;

  Scenario() {
    UnitTypeConfig cfg = AcceleratorConfig().trv;
    cfg.l1.hit_latency = uint32_t(kL1Hit);
    cfg.l1.ports = 0;
    b = std::make_unique<LoneTrv>("lone", image, cfg);
    RayInfo info;
    info.ray = bench::down_at(8.f);
    ray = b->pool.create(info);
    b->trv.in.push(ray, at(kStart), at(kStart));
    test::simulate();
    while (!b->to_list.empty()) {
      const uint64_t c = cycle_of(b->to_list.head_ready());
      out.push_back({b->to_list.pop(at(bench::kEndCycle)), c});
    }
  }
  // The nodes the ray fetches, and the lines they lie on (8 nodes a line).
  std::vector<uint32_t> path() const {
    std::vector<uint32_t> p{0};
    while (!tree.nodes[p.back()].is_leaf()) {
      const KdNode& n = tree.nodes[p.back()];
      p.push_back(Vec3(8.f, 0.f, -5.f)[n.axis()] < n.split() ? p.back() + 1 : n.above_child());
    }
    return p;
  }
  uint64_t lines() const {
    uint64_t n = 0, last = ~uint64_t(0);
    for (uint32_t node : path()) n += node / 8 != last ? (last = node / 8, 1) : 0;
    return n;
  }
};

Scenario& run() {
  static Scenario s;
  return s;
}

TEST(ScriptedLevel, ATrvUnitWalksOnItInTheClosedForm) {
  Scenario& s = run();
  const uint64_t nodes = s.path().size(), lines = s.lines();
  ASSERT_GE(nodes, 2u);
  ASSERT_EQ(s.out.size(), 1u);
  EXPECT_EQ(s.out[0].first, s.ray);
  EXPECT_EQ(s.out[0].second,
            kStart + nodes * kLatency + lines * (kL1Hit + kLevel) + (nodes - lines) * kL1Hit);
}

TEST(ScriptedLevel, SeesOneRequestPerLineAfterTheL1TagCheck) {
  Scenario& s = run();
  ASSERT_EQ(s.b->level.asked.size(), s.lines());
  EXPECT_EQ(s.b->level.asked[0].second, at(kStart + kL1Hit)) << "the root's line, asked first";
  EXPECT_EQ(s.b->trv.l1().stats().misses, s.lines());
}

}  // namespace
}  // namespace rtsim::model
