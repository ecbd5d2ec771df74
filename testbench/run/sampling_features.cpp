#include "testbench/run/sampling_features.h"

namespace rtsim {

FrameFeatures run_batch_features(const PreparedScene& p, const model::AcceleratorConfig& hw,
                                 const RunSettings& run, FeaturePassOptions options) {
  options.culling = run.lvb;
  const bool shadows = hw.schedule == model::Schedule::kTwoPhase;
  return model::frame_batch_features(*p.image, p.scene.camera, p.scene.width, p.scene.height, hw,
                                     options, shadows);
}

}  // namespace rtsim
