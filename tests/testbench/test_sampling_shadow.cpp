// The functional pass's shadow phase (model/functional/batch_features.h) against the model over the
// city with its lights and LVB culling, two phases: the shadow rays it emits and culls are the
// culling unit's, per light in all; the reads of TRV, LIST and IST over both phases are the
// model's units', record for record and line for line; it has as many shadow batches as the
// model. The caches' misses and the replay's cycles are only printed and bounded (the pass
// approximates the model's timing). The walks traced ahead on a thread give the same features,
// and the walk steps Neyman's strata are cut on are the reference tracer's. (One SystemC simulation
// per executable.)
#include "kernels/reference_tracer.h"
#include "model/accelerator.h"
#include "testbench/run/pipeline.h"
#include "testbench/run/sampling_features.h"
#include "tests/test_util.h"
#include "tests/testbench/sampling_counts.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cstdio>
#include <numeric>

namespace rtsim {
namespace {

constexpr int kW = 96, kH = 54;

// The city at kW x kH with its LVB words in the image.
PreparedScene city_with_lvb() {
  PreparedScene p = prepare_scene((test::source_dir() / "configs/scenes/city.yaml").string(),
                                  {"", {}, kW, kH, Accel::kKdTree});
  LvbParams lp;
  const LvbResult lvb = compute_scene_lvb(p, lp);
  for (uint32_t i = 0; i < lvb.words.size(); ++i) p.image->set_leaf_lvb(i, lvb.words[i]);
  return p;
}

TEST(SamplingFeatures, TheShadowPhaseEmitsCullsAndReadsWhatTheModelDoes) {
  sc_core::sc_set_time_resolution(1, sc_core::SC_PS);
  const PreparedScene p = city_with_lvb();
  model::AcceleratorConfig cfg;  // the paper's machine: two phases, records from memory
  model::Accelerator device("device", cfg, *p.image, model::FrameJob{p.scene.camera, kW, kH});
  test::simulate();
  const model::AcceleratorResult r = device.result();
  ASSERT_GT(r.shadow_rays, 0u);

  RunSettings run;
  run.lvb = true;
  const FrameFeatures f = run_batch_features(p, cfg, run);
  ASSERT_EQ(f.primary.size(), r.primary_batch_cycles.size());
  ASSERT_EQ(f.shadow.size(), r.shadow_batch_cycles.size());
  uint64_t emitted = 0, culled = 0, hits = 0, replay = 0;
  model::CacheCounts c;
  for (const BatchFeatures& b : f.primary) c.add(b.caches);
  for (const BatchFeatures& b : f.shadow) {
    c.add(b.caches);
    emitted += b.rays;
    culled += b.culled;
    hits += b.hits;
    replay += b.replay_cycles;
  }
  EXPECT_EQ(emitted, r.shadow_rays);
  EXPECT_EQ(culled, std::accumulate(r.shadow_culled.begin(), r.shadow_culled.end(), uint64_t(0)));
  EXPECT_EQ(hits, r.primary_hits);
  EXPECT_GT(culled, 0u);
  std::printf("shadow cycles: replay %llu, model %llu\n", (unsigned long long)replay,
              (unsigned long long)r.cycles_shadow);
  EXPECT_NEAR(double(replay), double(r.cycles_shadow), 0.35 * r.cycles_shadow);
  const nlohmann::json& s = r.stats;
  const auto at = test::count;
  test::expect_walk_reads(c, s);
  // Shading's L1: the hits' triangles and materials, and the culling unit's light reads (the
  // model reads a light's record again after a miss fills it: a few more).
  const uint64_t shading = test::stat(s, "shading", "l1", "accesses");
  std::printf("shading L1 lines: pass %llu, model %llu\n",
              (unsigned long long)at(c.l1_lines, model::kShadingStage),
              (unsigned long long)shading);
  EXPECT_NEAR(double(at(c.l1_lines, model::kShadingStage)), double(shading), 0.02 * shading);
}

// The walks traced ahead on a thread of their own, from the first walk or from the second chunk
// (as when a sampled run's second core comes free), give the same features, batch for batch.
TEST(SamplingFeatures, TracingAheadOnAThreadChangesNothing) {
  PreparedScene p = prepare_scene((test::source_dir() / "configs/scenes/city.yaml").string(),
                                  {"", {}, kW, kH, Accel::kKdTree});
  const model::AcceleratorConfig cfg;
  RunSettings run;
  run.lvb = false;  // every shadow ray traced
  FeaturePassOptions ahead;
  ahead.trace_ahead = true;
  const std::atomic<bool> free_core{true};  // seen when the first chunk is done
  FeaturePassOptions later;
  later.trace_ahead_from = &free_core;
  const FrameFeatures a = run_batch_features(p, cfg, run),
                      b = run_batch_features(p, cfg, run, ahead),
                      c = run_batch_features(p, cfg, run, later);
  ASSERT_FALSE(a.shadow.empty());
  const auto same = [](const BatchFeatures& x, const BatchFeatures& y) {
    return x.rays == y.rays && x.hits == y.hits && x.occluded == y.occluded &&
           x.replay_cycles == y.replay_cycles && x.caches.l1_misses == y.caches.l1_misses &&
           x.caches.l2_misses == y.caches.l2_misses && x.caches.reads == y.caches.reads;
  };
  for (const FrameFeatures* x : {&b, &c}) {
    ASSERT_EQ(a.primary.size(), x->primary.size());
    ASSERT_EQ(a.shadow.size(), x->shadow.size());
    for (size_t i = 0; i < a.primary.size(); ++i)
      EXPECT_TRUE(same(a.primary[i], x->primary[i])) << i;
    for (size_t i = 0; i < a.shadow.size(); ++i) EXPECT_TRUE(same(a.shadow[i], x->shadow[i])) << i;
  }
}

// The strata's auxiliary (batch_walk_steps): the reference tracer's frame with culling off takes
// as many walk steps as the batches add up to, with the LVB words set; one ray in 4 a part of it.
TEST(SamplingFeatures, TheWalkStepsAreTheReferenceFramesWithCullingOff) {
  const PreparedScene p = city_with_lvb();
  const model::AcceleratorConfig cfg;
  const std::vector<double> steps = batch_walk_steps(*p.image, p.scene.camera, kW, kH, cfg);
  TracerOptions o;
  o.width = kW;
  o.height = kH;
  o.threads = 1;
  const TraceStats ref = ReferenceTracer(*p.image).trace_frame(p.scene.camera, o).stats;
  ASSERT_GT(ref.any.tri_tests, 0u);
  const auto sum = [](const std::vector<double>& v) {
    return std::accumulate(v.begin(), v.end(), 0.0);
  };
  EXPECT_EQ(sum(steps), double(ref.closest.nodes + ref.closest.leaves + ref.closest.tri_tests +
                               ref.any.nodes + ref.any.leaves + ref.any.tri_tests));
  EXPECT_EQ(steps.size(), size_t((kW * kH + 63) / 64));
  const double quarter = sum(batch_walk_steps(*p.image, p.scene.camera, kW, kH, cfg, 4));
  EXPECT_GT(quarter, 0.15 * sum(steps));
  EXPECT_LT(quarter, 0.35 * sum(steps));
}

}  // namespace
}  // namespace rtsim
