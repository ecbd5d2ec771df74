#include "testbench/sampling_features.h"

#include "testbench/sampling_replay.h"

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
