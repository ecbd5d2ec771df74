// The functional pass of a sampled frame (model/functional/batch_features.h) against the model:
// over a frame of primary rays only (the city without its lights: no shadow phase), the reads of
// each unit type in the reference tracer's access stream (kernels/access_stream.h) are the reads
// the model's units made, record for record and line for line. The caches' misses and the replay's
// cycles are not compared exactly (the model's depend on its timing, which the pass only
// approximates), only printed and bounded. (One SystemC simulation per executable.)
#include "config_loader/scene_file.h"
#include "kernels/kdtree.h"
#include "kernels/memory_image.h"
#include "model/accelerator.h"
#include "model/functional/functional_pass.h"
#include "testbench/run/sampling_features.h"
#include "testbench/sampling/sample_pass_file.h"
#include "tests/test_util.h"
#include "tests/testbench/sampling_counts.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numeric>
#include <random>
#include <sstream>

namespace rtsim {
namespace {

constexpr int kW = 96, kH = 54;

struct PrimaryOnlyCity {
  PrimaryOnlyCity() {
    const SceneSetup setup =
        load_scene_file((test::source_dir() / "configs/scenes/city.yaml").string());
    scene = setup.scene;
    scene.lights.clear();
    tree = build_kdtree(scene.triangles, setup.kdtree);
    image = std::make_unique<MemoryImage>(scene, tree);
  }
  Scene scene;
  KdTree tree;
  std::unique_ptr<MemoryImage> image;
};

using test::stat;

TEST(CacheTags, EvictsTheLeastRecentlyUsedLineOfItsSet) {
  model::CacheConfig cfg;
  cfg.size_bytes = 4 * 64;
  cfg.ways = 2;
  cfg.line_bytes = 64;
  model::CacheTags c(cfg);  // two sets of two ways
  EXPECT_FALSE(c.access(0));
  EXPECT_FALSE(c.access(2));  // the same set (even lines)
  EXPECT_FALSE(c.access(1));  // the other set
  EXPECT_TRUE(c.access(0));   // 0 is now the most recent of its set
  EXPECT_FALSE(c.access(4));  // evicts 2
  EXPECT_TRUE(c.access(0));
  EXPECT_TRUE(c.access(4));
  EXPECT_FALSE(c.access(2));
  EXPECT_TRUE(c.access(1));  // untouched by the other set
}

TEST(PortCalendar, ALineTakesTheFirstFreeCyclesFromWhenItIsReady) {
  model::functional::PortCalendar port;
  EXPECT_EQ(port.book(0, 10, 3), 13u);  // cycles 10-12
  EXPECT_EQ(port.book(0, 11, 3), 16u);  // queues behind it: 13-15
  // Booked later but ready earlier (an L2 hit made after a DRAM line): it does not queue behind
  // the later lines, it takes the free cycles before them.
  EXPECT_EQ(port.book(0, 2, 3), 5u);
  EXPECT_EQ(port.book(0, 6, 3), 9u);
  EXPECT_EQ(port.book(0, 8, 3), 19u);  // 9 is free, 10-15 are not: 16-18
  EXPECT_EQ(port.book(0, 7, 2), 21u);  // 9 alone is too short: 19-20
}

// The calendar's skip links are a speed-up only: it books what a search of one cycle at a time
// books, also when the reads' times go back and forth (a slot of the window then changes hands
// between a later and an earlier cycle).
TEST(PortCalendar, BooksWhatACycleByCycleSearchBooks) {
  struct Plain {  // the first fit of PortCalendar::book, searched one cycle at a time
    uint64_t book(uint64_t now, uint64_t t, uint32_t cycles) {
      for (bool after_all = t >= tail; !after_all;) {  // then every cycle from t is free
        if (t + cycles > now + 512) return t + cycles;
        uint32_t k = 0;
        while (k < cycles && tag[(t + k) % 512] != t + k + 1) ++k;
        if (k == cycles) break;
        t += k + 1;  // past the booked cycle
      }
      for (uint32_t k = 0; k < cycles; ++k) tag[(t + k) % 512] = t + k + 1;
      tail = std::max(tail, t + cycles);
      return t + cycles;
    }
    uint64_t tail = 0;
    std::vector<uint64_t> tag = std::vector<uint64_t>(512, 0);
  };
  for (uint32_t cycles : {1u, 3u}) {
    Plain plain;
    model::functional::PortCalendar port;
    std::mt19937_64 rng(cycles);
    uint64_t clock = 1000, differ = 0, deferred = 0;
    for (int i = 0; i < 200000; ++i) {
      clock += rng() % 3;  // a read's time: the clock give or take a port's queue
      const uint64_t now = clock + rng() % 700 - 300;
      const uint64_t t = now + rng() % 40 + (rng() % 8 == 0 ? rng() % 600 : 0);
      const uint64_t a = plain.book(now, t, cycles), b = port.book(now, t, cycles);
      differ += a != b;
      deferred += a > now + 512;
    }
    EXPECT_EQ(differ, 0u) << cycles << " cycles a line";
    EXPECT_GT(deferred, 0u);  // the window's end was reached
  }
}

// run.sample_grow's attempts share the first one's pass through a file: read back, it is the pass
// to the last bit; a file kept for another run's settings, or cut short, is refused.
TEST(SampledPassFile, KeepsThePassBitForBitAndRefusesAnotherRunsOrABrokenOne) {
  const SceneSetup setup =
      load_scene_file((test::source_dir() / "configs/scenes/city.yaml").string());
  const KdTree tree = build_kdtree(setup.scene.triangles, setup.kdtree);
  const MemoryImage image(setup.scene, tree);
  const model::AcceleratorConfig cfg;
  SampledPass pass;
  pass.features = frame_batch_features(image, setup.scene.camera, kW, kH, cfg);
  pass.walk_steps = batch_walk_steps(image, setup.scene.camera, kW, kH, cfg);
  ASSERT_FALSE(pass.features.shadow.empty());
  const std::filesystem::path dir = test::temp_dir("sampled_pass_file");
  const PassKeeping keep{(dir / "pass.bin").string(), "the run's settings"};
  EXPECT_FALSE(read_sampled_pass(keep).has_value());  // none kept yet
  write_sampled_pass(keep, pass);

  const std::optional<SampledPass> back = read_sampled_pass(keep);
  ASSERT_TRUE(back.has_value());
  const auto csv = [](const FrameFeatures& f) {
    std::ostringstream out;
    write_features_csv(out, f);
    return out.str();
  };
  EXPECT_EQ(csv(back->features), csv(pass.features));
  EXPECT_EQ(back->walk_steps, pass.walk_steps);
  EXPECT_EQ(back->features.primary_seconds, pass.features.primary_seconds);
  EXPECT_EQ(back->features.shadow_seconds, pass.features.shadow_seconds);

  const auto refused = [](const PassKeeping& k, const std::string& why) {
    try {
      read_sampled_pass(k);
      ADD_FAILURE() << "read " << k.file;
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(k.file), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << e.what();
    }
  };
  refused(PassKeeping{keep.file, "another run's settings"}, "another run's settings");
  std::filesystem::resize_file(keep.file, std::filesystem::file_size(keep.file) - 9);
  refused(keep, "ends early");
  { std::ofstream(keep.file) << "rtsim run report\n"; }
  refused(keep, "not a kept functional pass");
  std::filesystem::remove_all(dir);
}

TEST(SamplingFeatures, TheAccessStreamReadsWhatTheModelsUnitsRead) {
  sc_core::sc_set_time_resolution(1, sc_core::SC_PS);
  const PrimaryOnlyCity city;
  model::AcceleratorConfig cfg;  // the paper's machine
  model::Accelerator device("device", cfg, *city.image, model::FrameJob{city.scene.camera, kW, kH});
  test::simulate();
  const model::AcceleratorResult r = device.result();
  ASSERT_EQ(r.shadow_rays, 0u);

  const std::vector<BatchFeatures> batches =
      primary_batch_features(*city.image, city.scene.camera, kW, kH, cfg);
  ASSERT_EQ(batches.size(), r.primary_batch_cycles.size());
  model::CacheCounts c;
  uint64_t rays = 0, hits = 0, replay_cycles = 0;
  for (const BatchFeatures& b : batches) {
    c.add(b.caches);
    rays += b.rays;
    hits += b.hits;
    replay_cycles += b.replay_cycles;
  }
  EXPECT_EQ(rays, uint64_t(kW * kH));
  EXPECT_EQ(hits, r.primary_hits);
  // The replay's clock is a rough one: within 30% of the model's cycles here.
  std::printf("cycles: replay %llu, model %llu\n", (unsigned long long)replay_cycles,
              (unsigned long long)r.cycles_primary);
  EXPECT_NEAR(double(replay_cycles), double(r.cycles_primary), 0.3 * r.cycles_primary);
  const auto at = test::count;
  const nlohmann::json& s = r.stats;
  EXPECT_GT(at(c.reads, model::kIstStage), 0u);
  test::expect_walk_reads(c, s);
  // Shading: the hit's triangle and its material.
  EXPECT_EQ(at(c.reads, model::kShadingStage), 2 * r.primary_hits);
  EXPECT_EQ(at(c.l1_lines, model::kShadingStage), stat(s, "shading", "l1", "accesses"));

  // The misses: the model's L1 misses against the pass's (a request the model merges into a
  // miss in flight is a hit in the pass), and its L2 misses (the shading L1s' on the IST's L2).
  const char* names[model::kStages] = {"trv", "list", "ist", "shading"};
  for (int u = 0; u < model::kStages; ++u) {
    const uint64_t model_misses = stat(s, names[u], "l1", "misses");
    std::printf("%s: L1 misses %llu (model: %llu), DRAM lines %llu\n", names[u],
                (unsigned long long)c.l1_misses[u], (unsigned long long)model_misses,
                (unsigned long long)c.l2_misses[u]);
    EXPECT_NEAR(double(c.l1_misses[u]), double(model_misses), 0.2 * model_misses) << names[u];
  }
  for (int u = 0; u < 3; ++u) {
    const uint64_t lines = c.l2_misses[u] + (u == 2 ? c.l2_misses[3] : 0);
    const uint64_t model_lines = stat(s, names[u], "l2", "misses");
    std::printf("%s L2: DRAM lines %llu (model: %llu)\n", names[u], (unsigned long long)lines,
                (unsigned long long)model_lines);
    EXPECT_NEAR(double(lines), double(model_lines), 0.2 * model_lines) << names[u];
  }
}

}  // namespace
}  // namespace rtsim
