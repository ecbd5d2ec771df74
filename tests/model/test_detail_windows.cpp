// A sampled frame's windows of detail (Accelerator::sample, model/units/detail_window.h): one
// window over the whole frame is the full frame, cycle for cycle; windows with gaps give each
// pixel inside them the full frame's result and time each of their batches. The devices run side
// by side in one simulation, each on its own calendar and memory.
#include "model/accelerator.h"
#include "tests/model/city_frame.h"

#include <gtest/gtest.h>

#include <numeric>

namespace rtsim::model {
namespace {

constexpr int kW = 100, kH = 30;  // 3,000 rays: 46 whole batches and one of 56

std::unique_ptr<Accelerator> device(const char* name, const test::CityFrame& city,
                                    const std::vector<DetailWindow>& windows) {
  auto d = std::make_unique<Accelerator>(name, AcceleratorConfig{}, *city.image,
                                         FrameJob{city.scene.camera, kW, kH});
  if (!windows.empty()) d->sample(windows);
  return d;
}

uint64_t sum(const std::vector<uint64_t>& v) { return std::accumulate(v.begin(), v.end(), 0ull); }

TEST(DetailWindows, OneWindowIsTheFullFrameAndGapsKeepEachWindowsPixels) {
  sc_core::sc_set_time_resolution(1, sc_core::SC_PS);
  const test::CityFrame city(kW, kH);
  const std::vector<DetailWindow> gaps = {{0, 640}, {1280, 1920}, {2560, 3000}};
  auto full = device("full", city, {});
  auto one = device("one", city, whole_frame(kW * kH));
  auto windowed = device("windowed", city, gaps);
  test::simulate();
  const AcceleratorResult f = full->result(), o = one->result(), w = windowed->result();

  // One window over every ray and slot: the same frame, cycle for cycle.
  EXPECT_EQ(o.cycles_total, f.cycles_total);
  EXPECT_EQ(o.cycles_primary, f.cycles_primary);
  EXPECT_EQ(o.stats, f.stats);
  ASSERT_EQ(o.primary_windows.size(), 1u);
  ASSERT_EQ(o.shadow_windows.size(), 1u);
  EXPECT_EQ(o.primary_windows[0].cycles, f.primary_batch_cycles);
  EXPECT_EQ(o.shadow_windows[0].cycles, f.shadow_batch_cycles);
  EXPECT_EQ(sum(f.shadow_batch_cycles), f.cycles_shadow);

  // Three windows: 10, 10 and 7 batches in each phase. The first begins as the full frame does,
  // so until its end (the issue of ray 640) its batches are the full frame's.
  ASSERT_EQ(w.primary_windows.size(), 3u);
  ASSERT_EQ(w.shadow_windows.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(w.primary_windows[i].first_batch, gaps[i].begin / kBatchRays);
    EXPECT_EQ(w.primary_windows[i].cycles.size(), i < 2 ? 10u : 7u);
    EXPECT_EQ(w.shadow_windows[i].cycles.size(), i < 2 ? 10u : 7u);
  }
  EXPECT_EQ(
      w.primary_windows[0].cycles,
      std::vector<uint64_t>(f.primary_batch_cycles.begin(), f.primary_batch_cycles.begin() + 10));
  // The gaps are not simulated (the time is not less on a frame this small: each window drains
  // the machine and fills it again).
  EXPECT_LT(w.shadow_rays, f.shadow_rays);
  EXPECT_EQ(w.primary_rays, 640u + 640u + 440u + 2u);  // with the two rays that time the ends

  // Inside the windows every pixel is the full frame's; outside, none was shaded.
  const std::vector<uint32_t> order = issue_order(kW, kH, RayOrder::kTiles, 8);
  uint64_t inside = 0;
  for (uint64_t k = 0; k < order.size(); ++k) {
    const uint32_t px = order[k];
    const bool in = (k < 640) || (k >= 1280 && k < 1920) || (k >= 2560);
    const bool timing_ray = k == 640 || k == 1920;  // issued to time a window's end
    if (timing_ray) continue;
    if (in) {
      ++inside;
      EXPECT_EQ(w.frame.pixels[px].hit.tri, f.frame.pixels[px].hit.tri) << k;
      EXPECT_EQ(w.frame.pixels[px].occluded, f.frame.pixels[px].occluded) << k;
      EXPECT_EQ(w.frame.pixels[px].culled, f.frame.pixels[px].culled) << k;
    } else {
      EXPECT_EQ(w.frame.pixels[px].hit.tri, kNoHit) << k;
    }
  }
  EXPECT_EQ(inside, 1720u);
  EXPECT_EQ(city.mismatches(f.frame), 0);
}

TEST(DetailWindows, WindowsOffBatchesOrOutOfOrderAreRefused) {
  EXPECT_EQ(check_windows(whole_frame(3000), 3000), "");
  EXPECT_EQ(check_windows({{0, 640}, {704, 3000}}, 3000), "");  // a batch apart
  for (const std::vector<DetailWindow>& bad : {std::vector<DetailWindow>{{10, 640}},
                                               {{0, 650}},
                                               {{0, 640}, {640, 1280}},
                                               {{640, 1280}, {0, 64}},
                                               {{0, 3064}},
                                               {{64, 64}}})
    EXPECT_NE(check_windows(bad, 3000), "") << bad[0].begin << " " << bad[0].end;
}

TEST(DetailWindows, ABatchTheScanReachesAfterTheLastRetirementTakesNoTime) {
  // Two batches of a window that ends the phase; the scan reached the second at 5 ns, after the
  // last retirement at 3 ns (its records hold no ray to emit).
  const Clock clock(1.0);
  const WindowBatches w = window_batches(clock, {0, 128}, 128, {0, 5000}, 3000);
  ASSERT_EQ(w.cycles.size(), 2u);
  EXPECT_EQ(w.cycles[0], 5u);
  EXPECT_EQ(w.cycles[1], 0u);
}

TEST(DetailWindows, ASampledFrameWithReflectionsIsAConfigError) {
  sc_core::sc_set_time_resolution(1, sc_core::SC_PS);
  const test::CityFrame city(kW, kH);
  AcceleratorConfig cfg;
  cfg.reflection_depth = 1;
  Accelerator d("reflecting", cfg, *city.image, FrameJob{city.scene.camera, kW, kH});
  test::ExpectReports expect({"rtsim/config"});
  EXPECT_THROW(d.sample(whole_frame(kW * kH)), sc_core::sc_report);
}

}  // namespace
}  // namespace rtsim::model
