#include "testbench/sampling_features.h"

#include "model/units/ray_generator.h"
#include "testbench/sampling_replay.h"
#include "testbench/sampling_walks.h"

#include <algorithm>

namespace rtsim {

std::vector<BatchFeatures> primary_batch_features(const MemoryImage& image, const Camera& camera,
                                                  int width, int height,
                                                  const model::AcceleratorConfig& cfg,
                                                  const FeaturePassOptions& options) {
  return frame_batch_features(image, camera, width, height, cfg, options, false).primary;
}

FrameFeatures frame_batch_features(const MemoryImage& image, const Camera& camera, int width,
                                   int height, const model::AcceleratorConfig& cfg,
                                   const FeaturePassOptions& options, bool shadows) {
  return sampling_detail::Replay(image, camera, width, height, cfg, options).run(shadows);
}

FrameFeatures run_batch_features(const PreparedScene& p, const model::AcceleratorConfig& hw,
                                 const RunSettings& run, FeaturePassOptions options) {
  options.culling = run.lvb;
  const bool shadows = hw.schedule == model::Schedule::kTwoPhase;
  return frame_batch_features(*p.image, p.scene.camera, p.scene.width, p.scene.height, hw, options,
                              shadows);
}

std::vector<double> batch_walk_steps(const MemoryImage& image, const Camera& camera, int width,
                                     int height, const model::AcceleratorConfig& cfg,
                                     uint32_t stride) {
  const std::vector<uint32_t> order = model::issue_order(width, height, cfg.order, cfg.tile);
  const ReferenceTracer tracer(image);
  const PinholeCamera cam(camera, width, height);
  const std::vector<image::LightRecord> lights = sampling_detail::image_lights(image);
  const float offset = sampling_detail::shadow_offset(image);
  std::vector<double> out((order.size() + model::kBatchRays - 1) / model::kBatchRays, 0.0);
  std::vector<Ray> shadows;
  for (size_t k = 0; k < order.size(); k += std::max<uint32_t>(1, stride)) {
    TraversalCounters c;
    const uint32_t pixel = order[k];
    const Ray ray = cam.ray(int(pixel % uint32_t(width)), int(pixel / uint32_t(width)));
    const Hit hit = tracer.closest_hit(ray, &c);
    if (hit.tri != kNoHit) {
      sampling_detail::hit_shadow_rays(image, lights, ray, hit, pixel, offset, false, shadows);
      for (const Ray& s : shadows) tracer.occluded(s, &c);
    }
    out[k / model::kBatchRays] += double(c.nodes + c.leaves + c.tri_tests);
  }
  return out;
}

void write_features_csv(std::ostream& out, const FrameFeatures& features) {
  static const char* const kTypes[kAccessUnits] = {"trv", "list", "ist", "shading"};
  out << "phase,batch,first_ray,rays,hits,culled,occluded,replay_cycles";
  for (const char* t : kTypes)
    out << ',' << t << "_reads," << t << "_l1_lines," << t << "_l1_misses," << t << "_dram_lines";
  out << '\n';
  const auto phase = [&out](const char* name, const std::vector<BatchFeatures>& batches) {
    for (size_t i = 0; i < batches.size(); ++i) {
      const BatchFeatures& b = batches[i];
      out << name << ',' << i << ',' << b.first_ray << ',' << b.rays << ',' << b.hits << ','
          << b.culled << ',' << b.occluded << ',' << b.replay_cycles;
      for (int t = 0; t < kAccessUnits; ++t)
        out << ',' << b.caches.reads[t] << ',' << b.caches.l1_lines[t] << ','
            << b.caches.l1_misses[t] << ',' << b.caches.l2_misses[t];
      out << '\n';
    }
  };
  phase("primary", features.primary);
  phase("shadow", features.shadow);
}

}  // namespace rtsim
