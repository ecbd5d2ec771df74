#include "model/functional/batch_features.h"

#include "model/accelerator_units.h"
#include "model/functional/functional_pass.h"
#include "model/functional/walks.h"
#include "model/units/ray_generator.h"

#include <algorithm>

namespace rtsim::model {

std::vector<BatchFeatures> primary_batch_features(const MemoryImage& image, const Camera& camera,
                                                  int width, int height,
                                                  const AcceleratorConfig& cfg,
                                                  const FeaturePassOptions& options) {
  return frame_batch_features(image, camera, width, height, cfg, options, false).primary;
}

FrameFeatures frame_batch_features(const MemoryImage& image, const Camera& camera, int width,
                                   int height, const AcceleratorConfig& cfg,
                                   const FeaturePassOptions& options, bool shadows) {
  return functional::Replay(image, camera, width, height, cfg, options).run(shadows);
}

std::vector<double> batch_walk_steps(const MemoryImage& image, const Camera& camera, int width,
                                     int height, const AcceleratorConfig& cfg, uint32_t stride) {
  const std::vector<uint32_t> order = issue_order(width, height, cfg.order, cfg.tile);
  const ReferenceTracer tracer(image);
  const PinholeCamera cam(camera, width, height);
  const std::vector<image::LightRecord> lights = functional::image_lights(image);
  const float offset = functional::shadow_offset(image);
  std::vector<double> out((order.size() + kBatchRays - 1) / kBatchRays, 0.0);
  std::vector<Ray> shadows;
  for (size_t k = 0; k < order.size(); k += std::max<uint32_t>(1, stride)) {
    TraversalCounters c;
    const uint32_t pixel = order[k];
    const Ray ray = cam.ray(int(pixel % uint32_t(width)), int(pixel / uint32_t(width)));
    const Hit hit = tracer.closest_hit(ray, &c);
    if (hit.tri != kNoHit) {
      functional::hit_shadow_rays(image, lights, ray, hit, pixel, offset, false, shadows);
      for (const Ray& s : shadows) tracer.occluded(s, &c);
    }
    out[k / kBatchRays] += double(c.nodes + c.leaves + c.tri_tests);
  }
  return out;
}

void write_features_csv(std::ostream& out, const FrameFeatures& features) {
  out << "phase,batch,first_ray,rays,hits,culled,occluded,replay_cycles";
  for (size_t s = 0; s < kStages; ++s) {
    const char* t = stage_name(Stage(s));
    out << ',' << t << "_reads," << t << "_l1_lines," << t << "_l1_misses," << t << "_dram_lines";
  }
  out << '\n';
  const auto phase = [&out](const char* name, const std::vector<BatchFeatures>& batches) {
    for (size_t i = 0; i < batches.size(); ++i) {
      const BatchFeatures& b = batches[i];
      out << name << ',' << i << ',' << b.first_ray << ',' << b.rays << ',' << b.hits << ','
          << b.culled << ',' << b.occluded << ',' << b.replay_cycles;
      for (size_t t = 0; t < kStages; ++t)
        out << ',' << b.caches.reads[t] << ',' << b.caches.l1_lines[t] << ','
            << b.caches.l1_misses[t] << ',' << b.caches.l2_misses[t];
      out << '\n';
    }
  };
  phase("primary", features.primary);
  phase("shadow", features.shadow);
}

WarmSource primary_warming(const MemoryImage& image, const Camera& camera, int width, int height,
                           const AcceleratorConfig& cfg, uint64_t rays) {
  if (rays == 0) return {};
  struct Pass {
    ReferenceTracer tracer;
    PinholeCamera camera;
    std::vector<uint32_t> order;
    int width;
    AccessStream stream;
  };
  auto pass = std::make_shared<Pass>(Pass{ReferenceTracer(image),
                                          PinholeCamera(camera, width, height),
                                          issue_order(width, height, cfg.order, cfg.tile),
                                          width,
                                          {}});
  return [pass, rays](uint64_t first, CacheWarmer& warmer) {
    const uint32_t units = warmer.traversal_units();
    for (uint64_t k = first > rays ? first - rays : 0; k < first; ++k) {
      const uint32_t px = pass->order[k];
      pass->stream.clear();
      pass->tracer.closest_hit(pass->camera.ray(int(px % pass->width), int(px / pass->width)),
                               pass->stream);
      for (const Access& a : pass->stream.reads)
        warmer.read(a.kind, uint32_t(k % units), a.addr, a.bytes);
    }
  };
}

}  // namespace rtsim::model
