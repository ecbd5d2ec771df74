// A sampled frame's functional warming (testbench/run/sampled_frame.h, primary_warming; the model's
// CacheWarmer): a window whose caches are warmed with the reads of the rays before it measures
// its batches about as the full frame does, closer than the same window with cold caches, and
// computes the same pixels; its caches hit as often as the full frame's over the same rays.
#include "config_loader/scene_file.h"
#include "kernels/kdtree.h"
#include "model/accelerator.h"
#include "testbench/run/sampled_frame.h"
#include "tests/model/city_frame.h"

#include <gtest/gtest.h>

#include <map>
#include <numeric>
#include <string>

namespace rtsim {
namespace {

constexpr int kW = 320, kH = 180;                 // a row of 8x8 tiles is 2,560 rays
constexpr uint64_t kBegin = 20480, kEnd = 24576;  // the window: 1,024 rays of warm-up, then 3,072
constexpr uint64_t kMeasured = (kEnd - kBegin - 1024) / model::kBatchRays;

std::unique_ptr<model::Accelerator> device(const char* name, const test::CityFrame& city,
                                           const std::vector<model::DetailWindow>& windows,
                                           model::WarmSource warm) {
  auto d = std::make_unique<model::Accelerator>(name, model::AcceleratorConfig{}, *city.image,
                                                model::FrameJob{city.scene.camera, kW, kH});
  if (!windows.empty()) d->sample(windows, std::move(warm));
  return d;
}

// The window's measured batches' cycles (its last kMeasured batches).
double measured(const model::AcceleratorResult& r) {
  const std::vector<uint64_t>& c = r.primary_windows.back().cycles;
  return std::accumulate(c.end() - kMeasured, c.end(), 0.0);
}

TEST(SampledWarming, AWarmedWindowMeasuresItsBatchesAsTheFullFrameDoes) {
  sc_core::sc_set_time_resolution(1, sc_core::SC_PS);
  const test::CityFrame city(kW, kH);
  const std::vector<model::DetailWindow> windows = {{0, 64}, {kBegin, kEnd}};
  auto full = device("full", city, {}, {});
  auto warmed = device("warmed", city, windows,
                       primary_warming(*city.image, city.scene.camera, kW, kH,
                                       model::AcceleratorConfig{}, 2 * 2560));
  auto cold = device("cold", city, windows, {});
  test::simulate();
  const model::AcceleratorResult f = full->result(), w = warmed->result(), c = cold->result();
  const size_t first = (kEnd / model::kBatchRays) - kMeasured;
  const double truth =
      std::accumulate(f.primary_batch_cycles.begin() + long(first),
                      f.primary_batch_cycles.begin() + long(first + kMeasured), 0.0);
  const double warm_error = std::abs(measured(w) / truth - 1);
  const double cold_error = std::abs(measured(c) / truth - 1);
  std::printf("measured batches: full %.0f, warmed %.0f (%.2f%%), cold %.0f (%.2f%%)\n", truth,
              measured(w), 100 * warm_error, measured(c), 100 * cold_error);
  EXPECT_LT(warm_error, 0.02);
  EXPECT_LT(warm_error, cold_error);
  // Warming changes the timing, never the data: the window's pixels are the full frame's.
  const std::vector<uint32_t> order = model::issue_order(kW, kH, model::RayOrder::kTiles, 8);
  for (uint64_t k = kBegin; k < kEnd; ++k)
    ASSERT_EQ(w.frame.pixels[order[k]].hit.tri, f.frame.pixels[order[k]].hit.tri) << k;
}

// Each unit type's L1 and L2 hits and accesses of a frame.
using CacheCounts = std::map<std::string, std::pair<double, double>>;
CacheCounts cache_counts(const model::AcceleratorResult& r) {
  CacheCounts out;
  for (const char* type : {"trv", "list", "ist", "shading"})
    for (const char* level : {"l1", "l2"}) {
      // A type without a cache of its own at a level (shading's L2 is the IST's) has no entry:
      // looked up with find, as a const json's operator[] must not be asked for a missing key.
      const auto t = r.stats.find(type);
      if (t == r.stats.end() || !t->contains(level)) continue;
      const nlohmann::json& c = (*t)[level];
      if (c.is_object())
        out[std::string(type) + "." + level] = {c["hits"].get<double>(),
                                                c["accesses"].get<double>()};
    }
  return out;
}

// a - b, cache by cache: the accesses of the rays one frame ran and the other did not.
CacheCounts minus(const CacheCounts& a, const CacheCounts& b) {
  CacheCounts out = a;
  for (auto& [name, c] : out) {
    c.first -= b.at(name).first;
    c.second -= b.at(name).second;
  }
  return out;
}

// The acceptance's test (issue 38): the caches' hit rates over a window's rays, warmed, against
// the full frame's over the same rays. The full frame's are a window from ray 0 to the window's
// end less one from ray 0 to its start (a window from ray 0 runs as the full frame does); the
// sampled window's are the frame with it less the frame with its first window alone. Primary rays
// only (a city without lights): the shadow phase's caches are not warmed functionally.
// With the default warming (one row of tiles, here 2,560 rays) every L1 hits within a point of
// the full frame (0.11 points here); the L2s keep lines over more rows (the LIST's misses by 1.3
// points here), and warming with every ray before the window brings them within a point too.
TEST(SampledWarming, AWarmedWindowsCachesHitAsTheFullFramesDoOverTheSameRays) {
  sc_core::sc_set_time_resolution(1, sc_core::SC_PS);
  const SceneSetup setup =
      load_scene_file((test::source_dir() / "configs/scenes/city.yaml").string());
  Scene scene = setup.scene;
  scene.lights.clear();
  const KdTree tree = build_kdtree(scene.triangles, setup.kdtree);
  const MemoryImage image(scene, tree);
  const model::AcceleratorConfig cfg;
  auto run = [&](const char* name, std::vector<model::DetailWindow> windows, uint64_t warming) {
    auto d = std::make_unique<model::Accelerator>(name, cfg, image,
                                                  model::FrameJob{scene.camera, kW, kH});
    d->sample(windows,
              warming ? primary_warming(image, scene.camera, kW, kH, cfg, warming) : nullptr);
    return d;
  };
  // Ten rows of tiles from the eighth: long enough that the rays in flight at its ends (768) are
  // few of its 25,600.
  const uint64_t row = 2560, begin = 8 * row, end = 18 * row;
  auto to_end = run("to_end", {{0, end}}, 0), to_begin = run("to_begin", {{0, begin}}, 0);
  auto first = run("first", {{0, 64}}, 0);
  auto one_row = run("one_row", {{0, 64}, {begin, end}}, row);
  auto every_ray = run("every_ray", {{0, 64}, {begin, end}}, begin);
  auto cold = run("cold", {{0, 64}, {begin, end}}, 0);
  test::simulate();
  const CacheCounts truth = minus(cache_counts(to_end->result()), cache_counts(to_begin->result()));
  const CacheCounts base = cache_counts(first->result());
  auto rate = [&](model::Accelerator& d, const std::string& name) {
    const auto c = minus(cache_counts(d.result()), base).at(name);
    return c.first / c.second;
  };
  double cold_worst = 0;
  for (const auto& [name, t] : truth) {
    const double full = t.first / t.second, warm = rate(*one_row, name),
                 all = rate(*every_ray, name), none = rate(*cold, name);
    std::printf("%s: full %.4f, one row %.4f, every ray %.4f, cold %.4f (%.0f accesses)\n",
                name.c_str(), full, warm, all, none, t.second);
    if (name.find(".l1") != std::string::npos) {
      EXPECT_NEAR(warm, full, 0.01) << name;
    }
    EXPECT_NEAR(all, full, 0.01) << name;
    cold_worst = std::max(cold_worst, std::abs(none - full));
  }
  EXPECT_GT(cold_worst, 0.01) << "cold caches should miss more: the test could not fail";
}

}  // namespace
}  // namespace rtsim
