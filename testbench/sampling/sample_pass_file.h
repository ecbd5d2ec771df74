// A sampled frame's functional pass and walk steps kept in a file between run.sample_grow's
// attempts (docs/sampling.md). Both depend on the scene, the hardware and the run's culling, never
// on the sample: an attempt at a larger fraction reads them instead of running the pass again,
// and estimates what a run at its fraction alone would, to the last digit.
#pragma once

#include "model/functional/batch_features.h"

#include <optional>
#include <string>
#include <vector>

namespace rtsim {

struct SampledPass {
  std::vector<double> walk_steps;  // batch_walk_steps per batch (empty: not counted)
  model::FrameFeatures features;
};

// Where an attempt keeps its pass, and what the pass depends on (the run's config.json without
// its sample settings): a file kept under another key is not this run's.
struct PassKeeping {
  std::string file, key;
};

// The pass kept in `keep.file`, or none when there is no such file. A file that is not one, or
// was kept under another key, is an error (std::runtime_error naming the file).
std::optional<SampledPass> read_sampled_pass(const PassKeeping& keep);

// Keeps `pass` in `keep.file` (written whole, then renamed into place).
void write_sampled_pass(const PassKeeping& keep, const SampledPass& pass);

}  // namespace rtsim
