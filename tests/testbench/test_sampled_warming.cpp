// A sampled frame's functional warming (testbench/sampled_frame.h, primary_warming; the model's
// CacheWarmer): a window whose caches are warmed with the reads of the rays before it measures
// its batches about as the full frame does, closer than the same window with cold caches, and
// computes the same pixels.
#include "model/accelerator.h"
#include "testbench/sampled_frame.h"
#include "tests/model/city_frame.h"

#include <gtest/gtest.h>

#include <numeric>

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

}  // namespace
}  // namespace rtsim
