// The shading unit on its own (tests/model/units/unit_bench.h): a finished ray with a hit fetches
// its triangle, then the triangle's material, through its L1 (which sits on the IST's L2), writes
// the hit into the FrameBuffer and its 64-byte record to memory through its `records` port at the
// time the shading completes, and retires; a mirror hands the ray back to its TRV unit as its
// reflection; a shadow ray only records whether it was blocked. Timing (docs/model-design.md):
// the material is asked for one cycle after the triangle at the earliest, and the shading
// completes at the material's delivery + the 4-cycle pipeline. One simulation for the file.
#include "model/units/shading_unit.h"

#include "tests/model/units/unit_bench.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <memory>

namespace rtsim::model {
namespace {

using namespace bench;

// The frame buffer's writes, recorded and passed on to memory.
class RecordingWriter : public sc_core::sc_object, public LineWriter {
 public:
  RecordingWriter(const char* name, LineWriter& to) : sc_core::sc_object(name), to_(to) {}
  void write_line(uint64_t line, const uint8_t* data, Tick when) override {
    written.push_back({line, std::vector<uint8_t>(data, data + kHitRecordBytes), when});
    to_.write_line(line, data, when);
  }
  bool full() const override { return to_.full(); }
  void on_room(std::function<void(Tick)> room) override { to_.on_room(std::move(room)); }
  std::vector<WrittenLine> written;

 private:
  LineWriter& to_;
};

// Triangle 0 (a diffuse material, 0) and triangle 1 (a mirror, material 1) at z = -5. Triangle 0
// is in the section's first line, triangle 1 straddles the first two; both 32-byte materials
// share one line.
Scene diffuse_and_mirror() {
  Scene s;
  Material diffuse, mirror;
  diffuse.diffuse = Vec3(0.25f, 0.5f, 0.75f);
  mirror.reflectance = 0.5f;
  s.add_material(diffuse);
  s.add_material(mirror);
  s.triangles.push_back({Vec3(-1.f, -1.f, -5.f), Vec3(1.f, -1.f, -5.f), Vec3(0.f, 1.f, -5.f), 0});
  s.triangles.push_back({Vec3(3.f, -1.f, -5.f), Vec3(5.f, -1.f, -5.f), Vec3(4.f, 1.f, -5.f), 1});
  return s;
}

constexpr uint64_t kLatency = 4;  // the shading pipeline (our default)
constexpr uint64_t kP = 10, kQ = 300, kM = 600, kS = 900, kN = 1200;
constexpr uint32_t kLvb = 0x3;

struct ShadingBench : Bench {
  ShadingBench(sc_core::sc_module_name name, const MemoryImage& image)
      : Bench(name, image, config()),
        shading("shading0", ctx, cfg.shading, &frame, records),
        writer("writer", memory.interconnect().writer(0)),
        written(writer.written) {
    frame.levels = 2;                // one mirror bounce
    ctx.light_samples.assign(2, 1);  // the shadow rays below go to lights 0 and 1, points
    frame.allocate(ctx.light_samples);
    shading.back.bind(*this);
    shading.records.bind(writer);
    attach(shading.mem_side, kShadingStage, 0);
  }
  ShadingUnit shading;
  RecordingWriter writer;
  const std::vector<WrittenLine>& written;
};

struct Scenario {
  Scene scene = diffuse_and_mirror();
  KdTree tree = build_kdtree(scene.triangles);
  MemoryImage image{scene, tree};
  std::unique_ptr<ShadingBench> b;
  uint32_t p = 0, q = 0, m = 0, s = 0, n = 0;

  // A ray down -z from (x, 0, 0) whose traversal ended, with a hit on `tri` at t = 5 or none.
  uint32_t ray(float x, uint32_t tri, uint32_t pixel, uint64_t cycle,
               RayType type = RayType::kPrimary) {
    const uint32_t id = b->add_ray({Vec3(x, 0.f, 0.f), Vec3(0.f, 0.f, -1.f)}, type, pixel);
    RayState& r = b->pool[id];
    r.ist.result.found = tri != kNoHit;
    r.ist.result.hit = {tri, 5.f, 0};
    r.ist.lvb = kLvb;
    r.info.light = 1;
    b->feed(&b->shading.in, id, cycle);
    return id;
  }

  Scenario() {
    b = std::make_unique<ShadingBench>("bench", image);
    p = ray(0.f, 0, 3, kP);                    // cold: the triangle's and the material's lines
    q = ray(0.f, 0, 5, kQ);                    // warm
    m = ray(4.f, 1, 7, kM);                    // a mirror: its triangle's second line is cold
    s = ray(0.f, 0, 3, kS, RayType::kShadow);  // blocked on the way to light 1 (entry 3)
    n = ray(0.f, kNoHit, 9, kN);               // a primary ray without a hit
    test::simulate();
    b->shading.finish_accounting(at(kEndCycle));
  }
};

Scenario& run() {
  static Scenario r;
  return r;
}

TEST(ShadingUnit, CompletesAtTheMaterialsDeliveryPlusThePipelineAndRetires) {
  Scenario& r = run();
  // P: the triangle is cold (kMiss); the material is asked one cycle after it came, also cold.
  // Q: the triangle hits (kL1Hit), the material one cycle later hits too. S and N: no fetch.
  const uint64_t p_done = kP + kMiss + 1 + kMiss + kLatency;
  const uint64_t q_done = kQ + std::max<uint64_t>(kL1Hit, 1) + kL1Hit + kLatency;
  ASSERT_EQ(r.b->retirements.size(), 4u);
  EXPECT_EQ(r.b->retirements[0], std::make_pair(RayType::kPrimary, at(p_done)));
  EXPECT_EQ(r.b->retirements[1], std::make_pair(RayType::kPrimary, at(q_done)));
  EXPECT_EQ(r.b->retirements[2], std::make_pair(RayType::kShadow, at(kS)));
  EXPECT_EQ(r.b->retirements[3], std::make_pair(RayType::kPrimary, at(kN)));
  EXPECT_EQ(r.b->retired, (std::vector<uint32_t>{r.p, r.q, r.s, r.n}));
  EXPECT_EQ(r.b->pool.in_flight(), 1u);              // the mirror's ray goes on as its reflection
  EXPECT_EQ(r.b->shading.stats().primary_rays, 4u);  // P, Q, the mirror's (before it reflects), N
  EXPECT_EQ(r.b->shading.stats().primary_hits, 3u);
  EXPECT_EQ(r.b->shading.stats().shadow_occluded, 1u);
}

TEST(ShadingUnit, WritesTheHitIntoTheFrameBufferAndItsRecordThroughItsRecordsPort) {
  Scenario& r = run();
  const PixelState& px = r.b->frame.at(3, 0);
  EXPECT_EQ(px.hit.tri, 0u);
  EXPECT_EQ(px.lvb, kLvb);
  EXPECT_EQ(px.surface.p, Vec3(0.f, 0.f, -5.f));
  EXPECT_EQ(px.diffuse, Vec3(0.25f, 0.5f, 0.75f));
  EXPECT_EQ(px.occluded, 1u << 1);  // the shadow ray to light 1
  EXPECT_EQ(r.b->frame.at(9, 0).hit.tri, kNoHit);
  // One record line per hit (P, Q, the mirror), at the entry's address, at the completion time.
  ASSERT_EQ(r.b->written.size(), 3u);
  const WrittenLine& w = r.b->written[0];
  EXPECT_EQ(w.line, r.b->records.address(3));
  EXPECT_EQ(w.when, at(kP + 2 * kMiss + 1 + kLatency));
  const HitRecord rec = decode_hit_record(w.bytes.data());
  EXPECT_TRUE(rec.hit);
  EXPECT_EQ(rec.lvb, kLvb);
  EXPECT_EQ(rec.surface.p, px.surface.p);
  // The record reached the memory: posted writes through the memory crossbar and the TLM port.
  EXPECT_EQ(r.b->ram.writes, 3u);
  const HitRecord stored = decode_hit_record(r.b->ram.bytes().data() + w.line);
  EXPECT_EQ(stored.lvb, kLvb);
  EXPECT_EQ(stored.surface.p, px.surface.p);
}

TEST(ShadingUnit, AMirrorHandsTheRayBackAsItsReflection) {
  Scenario& r = run();
  // The triangle's second line is cold (kMiss from kM); the material shares the warm line.
  ASSERT_EQ(r.b->returned.size(), 1u);
  EXPECT_EQ(r.b->returned[0].first, r.m);
  EXPECT_EQ(cycle_of(r.b->returned[0].second), kM + kMiss + 1 + kL1Hit + kLatency);
  const RayState& m = r.b->pool[r.m];
  EXPECT_EQ(m.info.type, RayType::kReflection);
  EXPECT_EQ(m.info.depth, 1u);
  EXPECT_EQ(m.info.entry, r.b->frame.entry(7, 1)) << "pixel 7, one bounce on";
  EXPECT_FALSE(m.ist.result.found) << "a new ray: no hit yet";
  EXPECT_GT(m.info.ray.d.z, 0.f);  // back up, away from the mirror
  EXPECT_EQ(r.b->frame.at(7, 0).hit.tri, 1u);
}

TEST(ShadingUnit, BusyStalledAndIdleCyclesAddUpToTheElapsedCycles) {
  Scenario& r = run();
  const UnitStats& s = r.b->shading.unit_stats();
  // Operations: P 4 (each fetch misses, then re-issues), Q 2, the mirror 3, S 1, N 1. The unit
  // holds a ray from its first operation to its last (Q's material goes when its triangle came).
  EXPECT_EQ(s.busy_cycles, 11u);
  const uint64_t held = (2 * kMiss + 2) + (std::max<uint64_t>(kL1Hit, 1) + 1) + (kMiss + 2) + 1 + 1;
  EXPECT_EQ(s.stalled_cycles, held - s.busy_cycles);
  EXPECT_EQ(s.idle_cycles, kEndCycle - held);
  EXPECT_EQ(s.busy_cycles + s.stalled_cycles + s.idle_cycles, kEndCycle);
}

}  // namespace
}  // namespace rtsim::model
