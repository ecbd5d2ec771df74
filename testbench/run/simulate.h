// The testbench's side of the model: it sets SystemC's time resolution, builds one Accelerator
// (model/accelerator.h), runs the simulation, maps the model's sc_reports to this program's errors,
// and composes the pixels' colours on the host from what the model computed.
#pragma once

#include "kernels/memory_image.h"
#include "model/accelerator.h"

#include <cstdint>
#include <vector>

namespace rtsim {

struct SimulatedFrame : model::AcceleratorResult {
  std::vector<uint8_t> rgb;     // composed on the host (compose_pixels, compose_paths)
  std::vector<float> radiance;  // a path-traced frame's linear RGB per pixel (compose_paths)
};

// Simulates one frame of `camera` over `image` at width x height, with SystemC's time resolution
// `resolution_ps` picoseconds (a power of ten). SystemC elaborates once per process: call this
// once. With `windows`, a sampled frame (Accelerator::sample). A watchdog stop or another model
// error becomes std::runtime_error, a configuration out of range (a resolution that cannot hold the
// clock included) InputError.
SimulatedFrame simulate_frame(const model::AcceleratorConfig& config, const MemoryImage& image,
                              const Camera& camera, int width, int height,
                              const model::SimulationHooks& hooks = {}, double resolution_ps = 1,
                              const std::vector<model::DetailWindow>& windows = {},
                              const model::WarmSource& warm = {});

// Runs the simulation until it ends (sc_start), mapping the model's sc_reports as simulate_frame
// does.
void run_simulation();

// The pixels, composed exactly as the reference tracer composes them: the local colour of each
// hit, blended with its reflection's from the deepest bounce up; 8-bit sRGB, row by row.
std::vector<uint8_t> compose_pixels(const model::FrameBuffer& frame, const MemoryImage& image);

// A path-traced frame's pixels, the mean of their paths as the reference tracer gathers them (the
// same order of float operations): linear RGB, row by row. display_bytes makes them 8-bit sRGB.
std::vector<float> compose_paths(const model::FrameBuffer& frame, const MemoryImage& image,
                                 const PathSettings& settings);
std::vector<uint8_t> display_bytes(const std::vector<float>& radiance);

}  // namespace rtsim
