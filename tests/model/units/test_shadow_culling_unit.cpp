// The shadow culling unit: at most its rate of hit records per cycle, one shadow ray per cycle,
// (reading the frame buffer from memory) rays built from the bytes it fetched, and an area light's
// records read once per (hit, light) pair.
// SystemC elaborates once per process: the scenarios run side by side in one simulation.
#include "model/units/shadow_culling_unit.h"

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
  std::vector<uint8_t> bytes;
  uint64_t reads = 0, last = 0;
};

struct Scenario {
  Scenario(const char* name, uint32_t rate, uint32_t lvb, size_t hits, size_t misses,
           bool from_memory, uint32_t samples = 1)
      : calendar((std::string(name) + "_calendar").c_str()),
        pool(4096),
        memory(samples),
        l1((std::string(name) + "_l1").c_str(), cache_config(), Clock(), &memory) {
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
    for (size_t i = 0; i < hits + misses; ++i) {
      PixelState& px = frame.pixels[i];
      if (i >= hits) continue;  // a miss: nothing written
      px.hit.tri = uint32_t(i);
      px.lvb = lvb;
      px.surface = {Vec3(float(i), 0.f, 0.f), Vec3(0.f, 1.f, 0.f)};
      // The memory's copy says the hit is 1000 higher: rays must come from it when reading memory.
      PixelState stored = px;
      stored.surface.p.y = 1000.f;
      encode_hit_record(stored, &memory.bytes[region.address(uint32_t(i))]);
    }
    for (auto& f : fifos) f = std::make_unique<RayFifo>(sc_core::sc_gen_unique_name("fifo"), 4096);
    CullingConfig cfg;
    cfg.records_per_cycle = rate;
    cfg.prefetch = 8;
    unit = std::make_unique<ShadowCullingUnit>(
        name, ctx, true, cfg, &l1, &frame, std::vector<RayFifo*>{fifos[0].get(), fifos[1].get()});
    if (from_memory) unit->read_records_from(&memory, region);
  }
  static CacheConfig cache_config() {
    CacheConfig c;
    c.size_bytes = 1024;
    c.hit_latency = 0;
    return c;
  }
  std::vector<Ray> rays() {
    std::vector<Ray> out;
    for (auto& f : fifos)
      while (!f->empty()) out.push_back(pool[f->pop(0)].trav.ray);
    return out;
  }

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
};

TEST(ShadowCullingUnit, TakesAtMostItsRateOfRecordsPerCycleAndOneRayPerCycle) {
  sc_core::sc_set_time_resolution(1, sc_core::SC_PS);
  // 12 hits whose lights are all culled, handed over in one phase: rate 1 takes 12 cycles, rate 4
  // takes 3, the ideal unit one.
  Scenario one("rate1", 1, 0u, 12, 0, false), four("rate4", 4, 0u, 12, 0, false),
      ideal("ideal", 0, 0u, 12, 0, false);
  // Reading the frame buffer: 3 hits with both lights to shoot, 5 misses, at one record per cycle.
  Scenario mem("memory", 1, 0b11u, 3, 5, true);
  // Area lights of 4 samples, light 1 culled: each (hit, light) pair shot reads its two records
  // once and holds them for the pair's samples.
  Scenario area("area", 1, 0b01u, 3, 0, false, 4);
  for (uint32_t e = 0; e < 3; ++e) area.unit->add(e, 0);
  area.unit->close(0);
  for (Scenario* s : {&one, &four, &ideal}) {
    for (uint32_t e = 0; e < 12; ++e) s->unit->add(e, 0);
    s->unit->close(0);
  }
  mem.unit->scan_all(0);
  test::simulate();

  EXPECT_EQ(one.unit->unit_stats().busy_cycles, 12u);
  EXPECT_EQ(four.unit->unit_stats().busy_cycles, 3u);
  EXPECT_EQ(ideal.unit->unit_stats().busy_cycles, 1u);
  for (Scenario* s : {&one, &four, &ideal}) {
    EXPECT_TRUE(s->unit->finished());
    EXPECT_EQ(s->unit->per_light()[0].culled, 12u);
    EXPECT_EQ(s->unit->generated(), 0u);
  }

  // Every entry's record was read once, and the six rays start at the stored points.
  EXPECT_TRUE(mem.unit->finished());
  EXPECT_EQ(mem.unit->generated(), 6u);
  const std::vector<Ray> rays = mem.rays();
  ASSERT_EQ(rays.size(), 6u);
  for (const Ray& r : rays)
    EXPECT_EQ(r.o.y, 1000.f) << "a ray built from the host's copy, not the fetched bytes";
  StatsRegistry reg;
  mem.unit->register_stats(reg, "c");
  EXPECT_EQ(reg.value("c.record_reads"), 8.0);
  EXPECT_EQ(reg.value("c.records_taken"), 8.0);

  EXPECT_TRUE(area.unit->finished());
  EXPECT_EQ(area.unit->generated(), 12u);
  EXPECT_EQ(area.unit->per_light()[1].culled, 12u);
  EXPECT_EQ(area.l1.stats().accesses, 6u) << "3 pairs x 2 records, not one read per sample";
  EXPECT_GE(area.unit->unit_stats().busy_cycles, 12u) << "one ray per cycle";
  std::vector<Ray> area_rays = area.rays();
  ASSERT_EQ(area_rays.size(), 12u);
  // The samples of a pair go to different points of the light (the edges were read).
  EXPECT_NE(area_rays[0].d, area_rays[1].d);
}

}  // namespace
}  // namespace rtsim::model
