// The shadow culling unit in each of its modes, bound to fakes (two TRV input FIFOs, an L1 over a
// fixed-latency memory holding the light records and the frame buffer's records): in two phases
// reading the records from memory (at most its rate of records per cycle, rays built from the
// bytes it fetched), in two phases as the ideal unit (any number of records a cycle from the
// host-side frame, entries without a hit skipped for free), in one phase at a limited rate (hits
// handed over as they are shaded), in one phase as the ideal unit; and an area light's records
// read once per (hit, light) pair. Always one shadow ray per cycle, culled lights skipped within
// the cycle. SystemC elaborates once per process: the scenarios run side by side in one
// simulation, built and run by the first test that asks.
#include "model/units/shadow_culling_unit.h"

#include "tests/model/at_start.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <cstring>
#include <memory>
#include <vector>

namespace rtsim::model {
namespace {

constexpr Tick kCycle = 1000;
constexpr uint32_t kLights = 2;
constexpr uint64_t kLightBase = 0;
constexpr uint64_t kRecordBase = 4096;

// Memory answering every line after 20 cycles, with two light records at 0 (points, or area
// lights of `samples` samples with their edge records after them) and whatever the test writes
// beyond.
class FixedMemory : public LineSource {
 public:
  explicit FixedMemory(uint32_t samples = 1) : bytes(1 << 16, 0) {
    for (uint32_t l = 0; l < kLights; ++l) {
      uint8_t* p = &bytes[kLightBase + l * image::kLightBytes];
      const float light[] = {10.f * float(l + 1), 100.f, 0.f, 0.f, 1.f, 1.f, 1.f, 0.f};
      std::memcpy(p, light, sizeof light);
      if (samples == 1) continue;
      const uint32_t flags = image::kLightArea | image::kLightTwoSided;
      std::memcpy(p + 12, &samples, 4);
      std::memcpy(p + 28, &flags, 4);
      const float edges[] = {1.f, 0.f, 0.f, 0.f, 0.f, 0.f, 1.f, 0.f};
      std::memcpy(&bytes[kLightBase + (kLights + l) * image::kLightBytes], edges, sizeof edges);
    }
  }
  Tick fetch_line(uint64_t line, Tick now, FillListener*, uint64_t) override {
    ++reads;
    last = line;
    return now + 20 * kCycle;
  }
  const uint8_t* line_data(uint64_t line) const override { return &bytes[line]; }
  uint32_t line_bytes() const override { return 64; }
  std::vector<uint8_t> bytes;
  uint64_t reads = 0, last = 0;
};

enum class Mode { kTwoPhasesFromMemory, kTwoPhasesIdeal, kOnePhase };

struct Scenario {
  // `hits` frame entries with a hit (LVB word `lvb`), then `misses` without; at `rate` records a
  // cycle (0: the ideal unit).
  Scenario(const std::string& name, Mode mode, uint32_t rate, uint32_t lvb, size_t hits,
           size_t misses, uint32_t samples = 1)
      : calendar((name + "_calendar").c_str()),
        pool(4096),
        memory(samples),
        l1((name + "_l1").c_str(), cache_config(), Clock(), &memory) {
    ctx.calendar = &calendar;
    ctx.pool = &pool;
    ctx.clock = Clock();
    ctx.header.light_count = kLights;
    ctx.header.lights = {uint32_t(kLightBase), kLights};
    ctx.shadow_offset = 0.f;
    ctx.light_samples.assign(kLights, samples);
    frame.width = int(hits + misses);
    frame.height = 1;
    frame.allocate(ctx.light_samples);
    for (size_t i = 0; i < hits; ++i) {
      PixelState& px = frame.pixels[i];
      px.hit.tri = uint32_t(i);
      px.lvb = lvb;
      px.surface = {Vec3(float(i), 0.f, 0.f), Vec3(0.f, 1.f, 0.f)};
      // The memory's copy says the hit is 1000 higher: rays must come from it when reading memory.
      PixelState stored = px;
      stored.surface.p.y = 1000.f;
      encode_hit_record(stored, &memory.bytes[region.address(uint32_t(i))]);
    }
    for (auto& f : fifos)
      f = std::make_unique<RayFifo>(sc_core::sc_gen_unique_name("fifo"), 4096, nullptr);
    CullingConfig cfg;
    cfg.records_per_cycle = rate;
    cfg.prefetch = 8;
    unit = std::make_unique<ShadowCullingUnit>(name.c_str(), ctx, cfg, nullptr, &frame, region);
    unit->begin_frame(true);
    for (auto& f : fifos) unit->to_trv.bind(*f);
    unit->lights.bind(l1);
    if (mode == Mode::kTwoPhasesFromMemory) unit->records.bind(memory);
    start = std::make_unique<test::AtStart>((name + "_start").c_str(), [this, mode, hits] {
      if (mode != Mode::kOnePhase) return unit->scan_all(0);
      for (uint32_t e = 0; e < hits; ++e) unit->hit_shaded(e, 0);
      unit->close(0);
    });
  }
  static CacheConfig cache_config() {
    CacheConfig c;
    c.size_bytes = 1024;
    c.hit_latency = 0;
    return c;
  }
  // The shadow rays it emitted, dealt in turn to the two FIFOs.
  std::vector<Ray> rays() {
    std::vector<Ray> out;
    for (auto& f : fifos)
      while (!f->empty()) out.push_back(pool[f->pop(0)].info.ray);
    return out;
  }
  uint64_t busy() const { return unit->unit_stats().busy_cycles; }

  Calendar calendar;
  RayPool pool;
  ModelContext ctx;
  FixedMemory memory;
  Cache l1;
  FrameBuffer frame;
  HitRecordRegion region = [] {
    HitRecordRegion r;
    r.base = kRecordBase;
    r.stride = kHitRecordBytes;
    return r;
  }();
  std::unique_ptr<RayFifo> fifos[2];
  std::unique_ptr<ShadowCullingUnit> unit;
  std::unique_ptr<test::AtStart> start;
};

struct Scenarios {
  // Two phases from memory: 3 hits with both lights to shoot, 5 misses, one record per cycle.
  Scenario memory{"memory", Mode::kTwoPhasesFromMemory, 1, 0b11u, 3, 5};
  // Two phases, ideal: 4 hits with light 0 culled, then 4 misses.
  Scenario ideal_scan{"ideal_scan", Mode::kTwoPhasesIdeal, 0, 0b10u, 4, 4};
  // One phase: 12 hits whose lights are all culled, at 1 and 4 records a cycle, and ideal.
  Scenario one{"rate1", Mode::kOnePhase, 1, 0u, 12, 0};
  Scenario four{"rate4", Mode::kOnePhase, 4, 0u, 12, 0};
  Scenario ideal{"ideal", Mode::kOnePhase, 0, 0u, 12, 0};
  // Area lights of 4 samples, light 1 culled: each (hit, light) pair shot reads its two records
  // once and holds them for the pair's samples.
  Scenario area{"area", Mode::kOnePhase, 1, 0b01u, 3, 0, 4};

  Scenarios() {
    sc_core::sc_set_time_resolution(1, sc_core::SC_PS);
    test::simulate();
  }
};

Scenarios& run() {
  static Scenarios s;
  return s;
}

TEST(ShadowCullingUnit, TwoPhasesFromMemoryReadsEveryRecordOnceAndBuildsRaysFromItsBytes) {
  Scenario& s = run().memory;
  EXPECT_TRUE(s.unit->finished());
  EXPECT_EQ(s.unit->generated(), 6u);
  const std::vector<Ray> rays = s.rays();
  ASSERT_EQ(rays.size(), 6u);
  for (const Ray& r : rays)
    EXPECT_EQ(r.o.y, 1000.f) << "a ray built from the host's copy, not the fetched bytes";
  StatsRegistry reg;
  s.unit->register_stats(reg, "c");
  EXPECT_EQ(reg.value("c.record_reads"), 8.0) << "every entry, the misses too";
  EXPECT_EQ(reg.value("c.records_taken"), 8.0);
  EXPECT_GE(s.busy(), 6u) << "one ray per cycle";
}

TEST(ShadowCullingUnit, TwoPhasesIdealSkipsEntriesWithoutAHitAndCulledLightsForFree) {
  Scenario& s = run().ideal_scan;
  EXPECT_TRUE(s.unit->finished());
  EXPECT_EQ(s.unit->generated(), 4u);
  EXPECT_EQ(s.unit->per_light()[0].culled, 4u);
  EXPECT_EQ(s.unit->per_light()[1].generated, 4u);
  // One cycle per ray: the culled light and the misses cost none, and no record is read.
  EXPECT_EQ(s.busy(), 4u);
  for (const Ray& r : s.rays()) EXPECT_EQ(r.o.y, 0.f) << "from the host-side frame";
  StatsRegistry reg;
  s.unit->register_stats(reg, "c");
  EXPECT_EQ(reg.value("c.record_reads"), 0.0);
}

TEST(ShadowCullingUnit, OnePhaseTakesAtMostItsRateOfRecordsPerCycle) {
  Scenarios& r = run();
  // 12 hits, all culled: rate 1 takes 12 cycles, rate 4 takes 3.
  EXPECT_EQ(r.one.busy(), 12u);
  EXPECT_EQ(r.four.busy(), 3u);
  for (Scenario* s : {&r.one, &r.four}) {
    EXPECT_TRUE(s->unit->finished());
    EXPECT_EQ(s->unit->per_light()[0].culled, 12u);
    EXPECT_EQ(s->unit->generated(), 0u);
  }
}

TEST(ShadowCullingUnit, OnePhaseIdealDecidesEveryCulledHitInOneCycle) {
  Scenario& s = run().ideal;
  EXPECT_TRUE(s.unit->finished());
  EXPECT_EQ(s.busy(), 1u);
  EXPECT_EQ(s.unit->per_light()[1].culled, 12u);
  EXPECT_EQ(s.unit->generated(), 0u);
}

TEST(ShadowCullingUnit, AnAreaLightsRecordsAreReadOncePerHitAndLight) {
  Scenario& s = run().area;
  EXPECT_TRUE(s.unit->finished());
  EXPECT_EQ(s.unit->generated(), 12u);
  EXPECT_EQ(s.unit->per_light()[1].culled, 12u);
  EXPECT_EQ(s.l1.stats().accesses, 6u) << "3 pairs x 2 records, not one read per sample";
  EXPECT_GE(s.busy(), 12u) << "one ray per cycle";
  std::vector<Ray> rays = s.rays();
  ASSERT_EQ(rays.size(), 12u);
  // The samples of a pair go to different points of the light (the edges were read).
  EXPECT_NE(rays[0].d, rays[1].d);
}

}  // namespace
}  // namespace rtsim::model
