// A sampled run's functional pass (model/functional/batch_features.h, the accelerator's functional
// mode), with the run's settings.
#pragma once

#include "model/functional/batch_features.h"
#include "testbench/run/pipeline.h"
#include "testbench/run/run_config.h"

namespace rtsim {

using model::BatchFeatures;
using model::FeaturePassOptions;
using model::FrameFeatures;

// The pass a run's settings ask for (the sampled run's call): the prepared scene at its resolution
// (its image with the LVB words when run.lvb), the hardware, LVB culling as run.lvb, the shadow
// phase in two phases.
FrameFeatures run_batch_features(const PreparedScene& p, const model::AcceleratorConfig& hw,
                                 const RunSettings& run, FeaturePassOptions options = {});

}  // namespace rtsim
